// libFuzzer harness: bytes -> a --scene JSON file -> pr::make_scene_spec (nlohmann::json parsing
// and our validation of objects, transforms, camera, light, size), then the built-in map specs it
// names ("builtin:NAME@WxH") through load_height/load_color. Files named by the scene are not
// opened (that is the other two harnesses' job). pr::Error is the expected outcome.
#include "app/options.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "fuzz_common.hpp"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto path = pr::fuzz::scratch_file(".json");
    pr::fuzz::write_bytes(path, data, size);
    pr::SceneOptions options;
    options.scene_file = path.string();
    pr::ImageLimits limits; // small built-in maps only: generating them is not what is tested
    limits.max_dimension = 512;
    limits.max_pixels = 1 << 16;
    try {
        const pr::SceneSpec spec = pr::make_scene_spec(options);
        for (const pr::ObjectSpec& o : spec.objects) {
            try {
                if (o.height.rfind("builtin:", 0) == 0) (void)pr::load_height(o.height, limits);
                if (o.color.rfind("builtin:", 0) == 0) (void)pr::load_color(o.color, limits);
            } catch (const pr::Error&) {
            }
        }
    } catch (const pr::Error&) {
    }
    return 0;
}
