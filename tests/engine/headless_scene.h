#pragma once
// A shipped scene with rendering, recording and the window switched off, for the runtime's tests.

#include <string>

#include "engine/runtime.h"

inline engine::SceneConfig headlessScene(const char* name) {
    engine::SceneConfig s = engine::loadScene(std::string(FLAGSIM_ASSETS_DIR) + "/scenes/" + name + ".json");
    s.subsystems &= ~(engine::kRender | engine::kRecording | engine::kWindow);
    return s;
}
