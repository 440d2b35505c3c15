#pragma once
// NVIDIA Newton's cloth solvers (VBD, XPBD, Style3D) as the study's solver kind nvidia_newton
// (nvidia_newton_kind.cpp), stepped by a Python process in the project's Newton venv.

namespace study {

// Adds the kind to the solver registry (once; later calls do nothing). Nothing starts until a
// flag steps with it.
void registerNvidiaNewton();

}  // namespace study
