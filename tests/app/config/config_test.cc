#include "app/config/config.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <set>
#include <sstream>

#include "engine/sim/multi_view_set.h"
#include "tests/common/test_data.h"

namespace semap::app {
namespace {

std::filesystem::path WriteYaml(const std::string& text) {
  const auto path = test::TempDir() / "config.yaml";
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const std::filesystem::path& path, const std::vector<std::string>& overrides = {}) {
  try {
    LoadConfig(path, overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, DefaultsLoadWithoutFile) {
  const Config c = LoadConfig("");
  EXPECT_EQ(c.input.layout, io::DatasetLayout::kAuto);
  EXPECT_EQ(c.input.max_frames, 0);
}

TEST(Config, FileAndOverridesApplyInOrder) {
  const auto path = WriteYaml("input:\n  max_frames: 20\n  layout: kitti_odometry\n");
  Config c = LoadConfig(path);
  EXPECT_EQ(c.input.max_frames, 20);
  EXPECT_EQ(c.input.layout, io::DatasetLayout::kKittiOdometry);
  c = LoadConfig(path, {"input.max_frames=5", "input.load_velodyne=false"});
  EXPECT_EQ(c.input.max_frames, 5);
  EXPECT_FALSE(c.input.load_velodyne);
}

TEST(Config, UnknownKeysAndSectionsAreErrorsNamingThem) {
  EXPECT_NE(ErrorOf(WriteYaml("input:\n  max_framez: 3\n")).find("input.max_framez"), std::string::npos);
  EXPECT_NE(ErrorOf(WriteYaml("inptu:\n  max_frames: 3\n")).find("'inptu'"), std::string::npos);
  EXPECT_NE(ErrorOf("", {"input.nope=1"}).find("input.nope"), std::string::npos);
  EXPECT_NE(ErrorOf("", {"input_max_frames=1"}).find("section.key=value"), std::string::npos);
}

TEST(Config, MalformedAndOutOfRangeValuesNameTheKey) {
  EXPECT_NE(ErrorOf("", {"input.max_frames=abc"}).find("input.max_frames"), std::string::npos);
  EXPECT_NE(ErrorOf("", {"input.layout=bogus"}).find("kitti_raw"), std::string::npos);
  const std::string range = ErrorOf("", {"input.max_frames=-3"});
  EXPECT_NE(range.find("input.max_frames"), std::string::npos) << range;
  EXPECT_NE(range.find("-3"), std::string::npos) << range;
}

TEST(Config, NonFiniteNumbersAreRefusedNamingTheKey) {
  for (const char* value : {".inf", "-.inf", ".nan"}) {
    const std::string override_error = ErrorOf("", {std::string("map.sigma_free_m=") + value});
    EXPECT_NE(override_error.find("'map.sigma_free_m': must be a finite number"), std::string::npos)
        << override_error;
    const std::string file_error = ErrorOf(WriteYaml(std::string("depth:\n  max_depth_m: ") + value + "\n"));
    EXPECT_NE(file_error.find("'depth.max_depth_m': must be a finite number"), std::string::npos)
        << file_error;
  }
}

TEST(Config, NumbersAreDumpedInTheirShortestExactForm) {
  Config c;
  c.map.sigma_free_m = 0.3;
  c.depth.max_depth_m = 100.0 / 3.0;
  c.pipeline.cpu_affinity = {0, 1};
  c.lcm.resend_bytes_per_s = 2e6;
  const std::string text = DumpConfig(c);
  EXPECT_NE(text.find("  sigma_free_m: 0.3\n"), std::string::npos);
  EXPECT_NE(text.find("  resend_bytes_per_s: 2000000\n"), std::string::npos);  // whole: no exponent
  EXPECT_NE(text.find("  max_depth_m: 33.333333333333336\n"), std::string::npos);
  EXPECT_NE(text.find("  cpu_affinity: [0, 1]\n"), std::string::npos);
  const Config back = LoadConfig(WriteYaml(text));
  EXPECT_EQ(back.map.sigma_free_m, 0.3);  // exact: the shortest form reads back to the same double
  EXPECT_EQ(back.depth.max_depth_m, 100.0 / 3.0);
  EXPECT_EQ(back.pipeline.cpu_affinity, (std::vector<int>{0, 1}));
  EXPECT_EQ(back.lcm.resend_bytes_per_s, 2e6);
}

TEST(Config, MissingOrInvalidFileIsAClearError) {
  EXPECT_NE(ErrorOf("/no/such/semap.yaml").find("/no/such/semap.yaml"), std::string::npos);
  const auto bad = WriteYaml("input: [1, 2\n");
  EXPECT_NE(ErrorOf(bad).find("not valid YAML"), std::string::npos);
}

TEST(Config, DumpRoundTripsAndDocumentsEveryKey) {
  Config c;
  c.input.max_frames = 42;
  const std::string text = DumpConfig(c);
  const auto path = WriteYaml(text);
  EXPECT_EQ(LoadConfig(path).input.max_frames, 42);
  // Every field line is preceded by a comment line.
  std::istringstream is(text);
  std::string line, previous;
  int fields = 0;
  while (std::getline(is, line)) {
    if (line.rfind("  ", 0) == 0 && line.rfind("  #", 0) != 0) {
      ++fields;
      EXPECT_EQ(previous.rfind("  # ", 0), 0u) << "undocumented: " << line;
    }
    previous = line;
  }
  EXPECT_GT(fields, 0);
}

// What an options struct's Describe() declares: each key with its text and the bytes of its member.
struct DescribedField {
  std::string key;
  std::string text;
  std::uintptr_t begin = 0;
  std::uintptr_t end = 0;
};

class DescribeRecorder {
 public:
  template <typename T, typename... Valid>
  void Field(std::string key, T* value, std::string text, const Valid&...) {
    Add(std::move(key), value, std::move(text));
  }
  template <typename E>
  void Enum(std::string key, E* value, std::vector<std::pair<std::string, E>> names, std::string text) {
    EXPECT_GE(names.size(), 2u) << key;
    Add(std::move(key), value, std::move(text));
  }
  std::vector<DescribedField> fields;

 private:
  template <typename T>
  void Add(std::string key, T* value, std::string text) {
    const auto begin = reinterpret_cast<std::uintptr_t>(value);
    fields.push_back({std::move(key), std::move(text), begin, begin + sizeof(T)});
  }
};

// Each key once, with a text; each described member inside the struct and described once; and no gap
// between described members wide enough to hold an undescribed member of 8 bytes or more (a double, a
// string, a vector): padding is narrower than that. (Members that are not config keys are narrower too:
// FrameSourceOptions::load_labels, a bool.)
template <typename Options>
void ExpectEveryMemberDescribedOnce(Options& options, const std::string& name) {
  DescribeRecorder r;
  options.Describe(r);
  ASSERT_FALSE(r.fields.empty()) << name;
  std::set<std::string> keys;
  for (const auto& f : r.fields) {
    EXPECT_TRUE(keys.insert(f.key).second) << name << "." << f.key << " described twice";
    EXPECT_FALSE(f.text.empty()) << name << "." << f.key << " has no text";
  }
  auto fields = r.fields;
  std::sort(fields.begin(), fields.end(), [](const auto& a, const auto& b) { return a.begin < b.begin; });
  const auto struct_begin = reinterpret_cast<std::uintptr_t>(&options);
  const auto struct_end = struct_begin + sizeof(Options);
  constexpr std::uintptr_t kNarrowerThanAnyWideMember = 8;
  std::uintptr_t covered_to = struct_begin;
  for (const auto& f : fields) {
    ASSERT_GE(f.begin, covered_to) << name << "." << f.key << " overlaps the member described before it";
    EXPECT_LT(f.begin - covered_to, kNarrowerThanAnyWideMember)
        << name << ": an undescribed member of " << (f.begin - covered_to) << " bytes before " << f.key;
    covered_to = f.end;
  }
  EXPECT_LE(covered_to, struct_end) << name;
  EXPECT_LT(struct_end - covered_to, kNarrowerThanAnyWideMember)
      << name << ": an undescribed member at the end";
}

TEST(Config, EveryOptionsStructDescribesEachMemberOnce) {
  Config c;
  ExpectEveryMemberDescribedOnce(c.input, "input");
  ExpectEveryMemberDescribedOnce(c.synth, "synth");
  ExpectEveryMemberDescribedOnce(c.pipeline, "pipeline");
  ExpectEveryMemberDescribedOnce(c.output, "output");
  ExpectEveryMemberDescribedOnce(c.lcm, "lcm");
  ExpectEveryMemberDescribedOnce(c.eval, "eval");
  ExpectEveryMemberDescribedOnce(c.depth, "depth");
  ExpectEveryMemberDescribedOnce(c.semantics, "semantics");
  ExpectEveryMemberDescribedOnce(c.simplify, "simplify");
  ExpectEveryMemberDescribedOnce(c.map, "map");
  ExpectEveryMemberDescribedOnce(c.odometry, "odometry");
  ExpectEveryMemberDescribedOnce(c.pose_input, "input (poses)");
  ExpectEveryMemberDescribedOnce(c.one_frame, "input (one frame)");
  ExpectEveryMemberDescribedOnce(c.plane_sweep, "plane_sweep");
  sim::MultiViewSetOptions multi_view_set;  // described, not a config section
  ExpectEveryMemberDescribedOnce(multi_view_set, "multi-view set");
}

TEST(Config, CommittedDefaultYamlMatchesTheCode) {
  const auto path = test::SourceDir() / "config" / "default.yaml";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::stringstream committed;
  committed << in.rdbuf();
  EXPECT_EQ(committed.str(), DumpConfig(Config{}))
      << "config/default.yaml is stale: regenerate with `semap config --defaults > config/default.yaml`";
}

// The presets shipped beside default.yaml load (every key known, every value in range) and set what they say.
TEST(Config, TheOneFramePresetLoads) {
  const Config c = LoadConfig(test::SourceDir() / "config" / "one_frame.yaml");
  EXPECT_EQ(c.depth.max_points_per_frame, 0);
  EXPECT_EQ(c.map.seen_noise_sigmas, 1.0);
  EXPECT_EQ(c.map.disparity_sigma_px, Config{}.map.disparity_sigma_px) << "a key the preset leaves alone";
}

// The preset built into the program is config/one_frame.yaml as it is now, and it loads under the config
// file and the --set overrides: what a run of one frame gets (input.one_frame_preset).
TEST(Config, TheOneFramePresetGoesUnderTheFileAndTheOverrides) {
  std::ifstream file(test::SourceDir() / "config" / "one_frame.yaml");
  std::stringstream committed;
  committed << file.rdbuf();
  EXPECT_EQ(OneFramePresetYaml(), committed.str()) << "the built-in preset is stale: rebuild";
  const Config preset_only = LoadConfig("", {}, OneFramePresetYaml());
  EXPECT_EQ(preset_only.depth.max_points_per_frame, 0);
  EXPECT_EQ(preset_only.map.seen_noise_sigmas, 1.0);
  const Config overridden = LoadConfig("", {"map.seen_noise_sigmas=0.5"}, OneFramePresetYaml());
  EXPECT_EQ(overridden.map.seen_noise_sigmas, 0.5);
  EXPECT_EQ(overridden.depth.max_points_per_frame, 0);
  const auto yaml = test::TempDir() / "budget.yaml";
  std::ofstream(yaml) << "depth:\n  max_points_per_frame: 5000\n";
  const Config from_file = LoadConfig(yaml, {}, OneFramePresetYaml());
  EXPECT_EQ(from_file.depth.max_points_per_frame, 5000);
  EXPECT_EQ(from_file.map.seen_noise_sigmas, 1.0);
  try {
    LoadConfig("", {}, "map:\n  no_such_key: 1\n");
    ADD_FAILURE() << "an unknown key in a preset must throw";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("preset: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("map.no_such_key"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace semap::app
