// Helpers of the io/sfm tests: comparing reconstructions, writing fixture files, expecting parse errors.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "io/file_error.h"
#include "io/sfm/sfm_reconstruction.h"
#include "tests/common/test_data.h"
#include "tests/io/sfm/sfm_street.h"

namespace semap::test {

inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

inline bool SamePixel(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.array().isNaN() == b.array().isNaN()).all() &&
         (a.array().isNaN() || a.array() == b.array()).all();
}

// Views (ids, names, intrinsics ids, poses within `pose_tolerance`), points (ids, positions, colours,
// labels) and observations (indices and pixels) equal. Intrinsics are compared by the caller (formats name
// models differently).
inline void ExpectSameScene(const io::SfmReconstruction& expected, const io::SfmReconstruction& actual,
                            double pose_tolerance = 1e-12) {
  ASSERT_EQ(expected.views.size(), actual.views.size());
  for (std::size_t v = 0; v < expected.views.size(); ++v) {
    const io::SfmView &e = expected.views[v], &a = actual.views[v];
    EXPECT_EQ(e.id, a.id) << "view " << v;
    EXPECT_EQ(e.name, a.name) << "view " << v;
    EXPECT_EQ(e.intrinsics_id, a.intrinsics_id) << "view " << v;
    EXPECT_LE((e.world_from_cam.matrix() - a.world_from_cam.matrix()).cwiseAbs().maxCoeff(), pose_tolerance)
        << "view " << v << "\n"
        << e.world_from_cam.matrix() << "\nvs\n"
        << a.world_from_cam.matrix();
  }
  ASSERT_EQ(expected.num_points(), actual.num_points());
  EXPECT_EQ(expected.point_ids, actual.point_ids);
  std::size_t differing = 0;
  for (std::size_t p = 0; p < expected.num_points(); ++p)
    differing += expected.points_world[p] != actual.points_world[p];
  EXPECT_EQ(differing, 0u) << "point positions differ";
  EXPECT_EQ(expected.point_colors_rgb, actual.point_colors_rgb);
  EXPECT_EQ(expected.point_labels, actual.point_labels);
  ASSERT_EQ(expected.observations.size(), actual.observations.size());
  differing = 0;
  for (std::size_t i = 0; i < expected.observations.size(); ++i) {
    const io::SfmObservation &e = expected.observations[i], &a = actual.observations[i];
    differing += e.point != a.point || e.view != a.view || !SamePixel(e.pixel_px, a.pixel_px);
  }
  EXPECT_EQ(differing, 0u) << "observations differ";
}

// A small street scene: 6 keyframes, 40 new points each, labels and colours.
inline io::SfmReconstruction SmallStreet() {
  SfmStreetOptions o;
  o.keyframes = 6;
  o.new_points_per_keyframe = 40;
  o.max_track_keyframes = 3;
  o.noise_m = 0.01;
  return MakeSfmStreet(SfmStreetScene(o), o);
}

// Runs `read` and expects a ParseError/FileError whose message contains every one of `parts`.
inline void ExpectReadError(const std::function<void()>& read, std::initializer_list<std::string> parts) {
  try {
    read();
    ADD_FAILURE() << "no error; expected one mentioning '" << *parts.begin() << "'";
  } catch (const io::FileError& e) {
    const std::string what = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
  }
}

// `j` written as `name` in the test's temporary folder.
inline std::filesystem::path WriteJson(const nlohmann::json& j, const std::string& name) {
  const auto path = TempDir() / name;
  WriteText(path, j.dump());
  return path;
}

// A change to a valid JSON document and the parts the reader's ParseError must name.
struct BadJsonCase {
  const char* name;
  std::function<void(nlohmann::json*)> change;
  std::vector<std::string> expected;
};

// For each case: `good` changed, written to `path`, read with `read`: a ParseError naming the file and every
// expected part.
inline void ExpectBadJsonCases(const nlohmann::json& good, const std::vector<BadJsonCase>& cases,
                               const std::filesystem::path& path,
                               const std::function<void(const std::filesystem::path&)>& read) {
  for (const BadJsonCase& c : cases) {
    SCOPED_TRACE(c.name);
    nlohmann::json j = good;
    c.change(&j);
    WriteText(path, j.dump());
    try {
      read(path);
      ADD_FAILURE() << "no error";
    } catch (const io::ParseError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.filename().string()), std::string::npos) << what;
      for (const auto& part : c.expected)
        EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
    }
  }
}

}  // namespace semap::test
