#include "io/sfm/internal/camera_models.h"

#include <array>
#include <stdexcept>

namespace semap::io::sfm_internal {
namespace {

// COLMAP's camera models (src/colmap/sensor/models.h), by id.
constexpr std::array<ColmapModel, 12> kColmapModels{{
    {0, "SIMPLE_PINHOLE", 3},
    {1, "PINHOLE", 4},
    {2, "SIMPLE_RADIAL", 4},
    {3, "RADIAL", 5},
    {4, "OPENCV", 8},
    {5, "OPENCV_FISHEYE", 8},
    {6, "FULL_OPENCV", 12},
    {7, "FOV", 5},
    {8, "SIMPLE_RADIAL_FISHEYE", 4},
    {9, "RADIAL_FISHEYE", 5},
    {10, "THIN_PRISM_FISHEYE", 12},
    {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16},
}};

constexpr std::array<OpenMvgModel, 6> kOpenMvgModels{{
    {"pinhole", "", 0},
    {"pinhole_radial_k1", "disto_k1", 1},
    {"pinhole_radial_k3", "disto_k3", 3},
    {"pinhole_brown_t2", "disto_t2", 5},
    {"fisheye", "fisheye", 4},
    {"spherical", "", -1},  // no focal length nor principal point: width and height only
}};

[[noreturn]] void NoEquivalent(const SfmIntrinsics& k, const char* target) {
  throw std::invalid_argument("camera " + std::to_string(k.id) + ": model " + k.model + " (" +
                              std::to_string(k.params.size()) + " parameters) has no exact " + target +
                              " equivalent");
}

SfmIntrinsics WithModel(const SfmIntrinsics& k, const char* model, std::vector<double> params) {
  SfmIntrinsics out = k;
  out.model = model;
  out.params = std::move(params);
  return out;
}

}  // namespace

std::optional<ColmapModel> ColmapModelByName(const std::string& name) {
  for (const ColmapModel& m : kColmapModels) {
    if (name == m.name) return m;
  }
  return std::nullopt;
}

std::optional<ColmapModel> ColmapModelById(int id) {
  for (const ColmapModel& m : kColmapModels) {
    if (id == m.id) return m;
  }
  return std::nullopt;
}

std::optional<OpenMvgModel> OpenMvgModelByName(const std::string& name) {
  for (const OpenMvgModel& m : kOpenMvgModels) {
    if (name == m.name) return m;
  }
  return std::nullopt;
}

SfmIntrinsics AsColmapModel(const SfmIntrinsics& k) {
  if (const auto m = ColmapModelByName(k.model)) {
    if (static_cast<int>(k.params.size()) != m->num_params) NoEquivalent(k, "COLMAP");
    return k;
  }
  const auto& p = k.params;
  if (k.model == "pinhole" && p.size() == 3) return WithModel(k, "SIMPLE_PINHOLE", p);
  if (k.model == "pinhole_radial_k1" && p.size() == 4) return WithModel(k, "SIMPLE_RADIAL", p);
  if (k.model == "pinhole_radial_k3" && p.size() == 6 && p[5] == 0.0) {
    return WithModel(k, "RADIAL", {p[0], p[1], p[2], p[3], p[4]});
  }
  NoEquivalent(k, "COLMAP");
}

SfmIntrinsics AsOpenMvgModel(const SfmIntrinsics& k) {
  if (const auto m = OpenMvgModelByName(k.model)) {
    const std::size_t expected =
        m->distortion_size < 0 ? 0 : 3 + static_cast<std::size_t>(m->distortion_size);
    if (k.params.size() != expected) NoEquivalent(k, "OpenMVG");
    return k;
  }
  if (k.params.empty() && !ColmapModelByName(k.model)) return k;  // a type read without parameters
  const auto& p = k.params;
  if (k.model == "SIMPLE_PINHOLE" && p.size() == 3) return WithModel(k, "pinhole", p);
  if (k.model == "PINHOLE" && p.size() == 4 && p[0] == p[1])
    return WithModel(k, "pinhole", {p[0], p[2], p[3]});
  if (k.model == "SIMPLE_RADIAL" && p.size() == 4) return WithModel(k, "pinhole_radial_k1", p);
  if (k.model == "RADIAL" && p.size() == 5)
    return WithModel(k, "pinhole_radial_k3", {p[0], p[1], p[2], p[3], p[4], 0.0});
  NoEquivalent(k, "OpenMVG");
}

}  // namespace semap::io::sfm_internal
