// The sciray tool's --material and --light JSON, as the tool reads them: the text through
// parse_json_argument (which turns nlohmann's exceptions into sciray::Error), then as a
// material and, apart, as a light.
#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "shading_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(sciray_fuzz::text_of(data, size));
  if (text.empty() || text.front() != '{') return 0;  // anything else is read as a file name
  return sciray_fuzz::run([&] {
    const nlohmann::json json = sciray_tool::parse_json_argument(text, "--material");
    sciray_fuzz::run([&] { sciray_tool::material_from_json(json, "--material"); });
    sciray_tool::light_from_json(json, "--light");
  });
}
