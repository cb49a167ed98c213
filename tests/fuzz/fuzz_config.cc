// Fuzzes the YAML config loader (with overrides) and the class-map loader.
#include "app/config/config.h"
#include "io/labels/class_map_yaml.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace semap;
  const auto path = fuzz::WriteInput("config.yaml", data, size);
  try {
    app::LoadConfig(path);
  } catch (const std::exception&) {
  }
  try {
    app::LoadConfig("", {std::string(reinterpret_cast<const char*>(data), size)});
  } catch (const std::exception&) {
  }
  try {
    io::LoadClassMap(path);
  } catch (const std::exception&) {
  }
  return 0;
}
