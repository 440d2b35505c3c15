// libFuzzer target for the scene and input-script parsers: any input must give a valid result or
// a ConfigError, never a crash, a hang or undefined behaviour.
//
//   clang++ ... -fsanitize=fuzzer,address,undefined; run: fuzz_parsers -max_total_time=60 corpus/

#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/scene/config_error.h"
#include "engine/scene/input_script.h"
#include "engine/scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    // Scene paths resolve against the shipped scenes folder, so model/script references may hit
    // real files too.
    const std::string where = std::string(FLAGSIM_ASSETS_DIR) + "/scenes/fuzz.json";
    try {
        engine::parseScene(text, where);
    } catch (const engine::ConfigError&) {
    }
    try {
        const engine::InputScript s = engine::InputScript::parse(text, "fuzz.json");
        (void)s.sample(s.duration() * 0.5);
    } catch (const engine::ConfigError&) {
    }
    return 0;
}
