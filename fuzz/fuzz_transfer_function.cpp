// The sciray tool's transfer function files (--tf), read over a data range of [0, 1].
#include "fuzz_support.hpp"
#include "volume_scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = sciray_fuzz::write_file("tf.json", sciray_fuzz::text_of(data, size));
  return sciray_fuzz::run([&] { sciray_tool::read_transfer_function(path.string(), {0.f, 1.f}); });
}
