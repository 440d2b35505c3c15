#pragma once
// NVIDIA Newton's cloth solvers (VBD, XPBD, Style3D) as the study's solver kind nvidia_newton
// (nvidia_newton_kind.cpp), stepped by a Python process in the project's Newton venv.

#include <string>

namespace study {

// Adds the kind to the solver registry (once; later calls do nothing). Nothing starts until a
// flag steps with it.
void registerNvidiaNewton();

// Why the kind cannot run here ("" when it can): its Python is not an executable file, named with
// how to make it. For a run to refuse before it writes anything.
std::string nvidiaNewtonUnavailable();

}  // namespace study
