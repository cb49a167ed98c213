// Fuzzes the reconstruction readers (io/sfm): the input is read as SLAM JSON and as OpenMVG JSON, and, split
// at the lines "@@" into cameras / images / points3D (+ points3D_labels), as a COLMAP text and a binary
// model.
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "app/sfm/sfm_mapping.h"
#include "io/sfm/colmap.h"
#include "io/sfm/openmvg.h"
#include "io/sfm/slam_json.h"
#include "tests/fuzz/fuzz_common.h"

namespace {

std::vector<std::string> Split(std::string_view text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t at; (at = text.find("\n@@\n", start)) != std::string_view::npos; start = at + 4) {
    parts.emplace_back(text.substr(start, at - start));
  }
  parts.emplace_back(text.substr(start));
  return parts;
}

void Read(const std::function<semap::io::SfmReconstruction()>& read) {
  try {
    semap::io::SfmReconstruction r = read();
    r.AssertConsistent();  // a reader must never return an inconsistent reconstruction
    // What map-sfm does next: points beyond the map's range are left out, consistently.
    semap::app::DropFarPoints("fuzz", semap::app::MaxSfmCoordinateM(semap::MapOptions{}), &r);
    r.AssertConsistent();
  } catch (const std::exception&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace semap;
  Read([&] { return io::ReadSlamJson(fuzz::WriteInput("slam.json", data, size)); });
  Read([&] { return io::ReadOpenMvgJson(fuzz::WriteInput("sfm_data.json", data, size)); });
  const auto parts = Split(std::string_view(reinterpret_cast<const char*>(data), size));
  const char* names[] = {"cameras", "images", "points3D", "points3D_labels"};
  for (const char* ext : {".txt", ".bin"}) {
    const auto dir = fuzz::ScratchDir() / (std::string("model") + ext);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (std::size_t i = 0; i < 4 && i < parts.size(); ++i) {
      const std::string file = std::string(names[i]) + (i == 3 ? ".txt" : ext);
      std::ofstream(dir / file, std::ios::binary) << parts[i];
    }
    Read([&] {
      return io::ReadColmapModel(
          dir, ext == std::string(".txt") ? io::ColmapEncoding::kText : io::ColmapEncoding::kBinary);
    });
  }
  return 0;
}
