// Each option's key is written once, in its options struct's Describe(); config/default.yaml holds every key
// declared there with its default.
//
// The sources of engine/, io/, app/ and tools/ are read as C++ text: a string literal that is a key ("key",
// "section.key", or an override or message that starts "section.key=" / "section.key:") outside its
// declaration is a key typed again, which a renamed or removed key would leave behind. Code names a key
// through the declaration instead: KeyOf(options, member) in the engine, app::ConfigKey / app::Override above
// it. Prose that mentions a key among other words (a help text, a doc text) is not checked. tests/ is not
// read: a test writes the keys a user types, on purpose, so that renaming one breaks it.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "app/config/config.h"
#include "engine/sim/multi_view_set.h"
#include "tests/common/test_data.h"

namespace semap::app {
namespace {

// Bare keys that are also, by coincidence, other names in the sources, each with where and why. A key added
// here must be one that cannot be told apart from such a name by its text.
const std::map<std::string, std::string>& AllowedBareKeys() {
  static const std::map<std::string, std::string> allowed = {
      {"near_m",
       "the near distance of engine/eval's own options (DepthRenderOptions, SurfaceMetricsOptions, "
       "not config keys: their Check() and eval.json name it), not synth.near_m"},
      {"poses", "the poses/ folder of a KITTI odometry root, and the \"poses\" messages of `semap view`"},
      {"method", "the \"method\" column of `semap table`'s table.json, the method of a row"},
  };
  return allowed;
}

struct DeclaredKey {
  std::string section;  // "" for an options struct that no config section binds
  std::string key;
};

// Every key an options struct declares: the config's sections, and the options that are described but not
// bound to the config (a struct described and missing here fails the test below: its keys appear once more
// in the sources than they are declared).
std::vector<DeclaredKey> DeclaredKeys() {
  std::vector<DeclaredKey> keys;
  Config config;
  for (const auto& section : BindSections(config)) {
    for (const auto& f : section.binder.fields()) keys.push_back({section.name, f.key});
  }
  sim::MultiViewSetOptions multi_view_set;  // `semap synth --layout strecha`'s set
  io::FieldBinder binder;
  multi_view_set.Describe(binder);
  for (const auto& f : binder.fields()) keys.push_back({"", f.key});
  return keys;
}

struct Literal {
  std::string text;    // as written between the quotes, escapes unexpanded
  std::size_t offset;  // of its opening quote (or of R of a raw string)
};

// The string literals of C++ source text, comments skipped (character literals and digit separators too).
std::vector<Literal> StringLiterals(const std::string& s) {
  std::vector<Literal> out;
  const auto identifier_char = [&](std::size_t i) {
    return std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '_';
  };
  std::size_t i = 0;
  while (i < s.size()) {
    if (s.compare(i, 2, "//") == 0) {
      i = s.find('\n', i);
      if (i == std::string::npos) break;
    } else if (s.compare(i, 2, "/*") == 0) {
      i = s.find("*/", i + 2);
      if (i == std::string::npos) break;
      i += 2;
    } else if (s[i] == '\'' && !(i > 0 && identifier_char(i - 1))) {  // a character literal, not 1'000
      std::size_t j = i + 1;
      while (j < s.size() && s[j] != '\'') j += s[j] == '\\' ? 2 : 1;
      i = j + 1;
    } else if (s[i] == 'R' && i + 1 < s.size() && s[i + 1] == '"' && !(i > 0 && identifier_char(i - 1))) {
      const std::size_t open = s.find('(', i);
      const std::string close = ")" + s.substr(i + 2, open - i - 2) + "\"";
      const std::size_t end = s.find(close, open);
      if (open == std::string::npos || end == std::string::npos) break;
      out.push_back({s.substr(open + 1, end - open - 1), i});
      i = end + close.size();
    } else if (s[i] == '"') {
      std::size_t j = i + 1;
      while (j < s.size() && s[j] != '"') j += s[j] == '\\' ? 2 : 1;
      out.push_back({s.substr(i + 1, j - i - 1), i});
      i = j + 1;
    } else {
      ++i;
    }
  }
  return out;
}

// True when the literal at `offset` is the first argument of a Describe() entry: v.Field("key", ...).
bool IsDeclaration(const std::string& s, std::size_t offset) {
  std::size_t end = offset;
  while (end > 0 && std::isspace(static_cast<unsigned char>(s[end - 1]))) --end;
  const auto ends_with = [&](const std::string& call) {
    return end >= call.size() && s.compare(end - call.size(), call.size(), call) == 0;
  };
  return ends_with("Field(") || ends_with("Enum(");
}

std::vector<std::filesystem::path> ScannedSources() {
  std::vector<std::filesystem::path> files;
  for (const char* dir : {"engine", "io", "app", "tools"}) {
    const auto root = test::SourceDir() / dir;
    for (auto it = std::filesystem::recursive_directory_iterator(root);
         it != std::filesystem::recursive_directory_iterator(); ++it) {
      if (it->is_directory() && it->path().filename() == "web") {  // semap view's page (JavaScript)
        it.disable_recursion_pending();
        continue;
      }
      const auto ext = it->path().extension();
      if (it->is_regular_file() && (ext == ".cc" || ext == ".h" || ext == ".in")) files.push_back(it->path());
    }
  }
  return files;
}

int LineOf(const std::string& text, std::size_t offset) {
  return 1 +
         static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

TEST(OptionKeys, EachKeyIsWrittenOnlyWhereItIsDeclared) {
  const std::vector<DeclaredKey> keys = DeclaredKeys();
  std::map<std::string, int> declarations;  // bare key → the options structs that declare it
  std::set<std::string> full_keys;          // "section.key"
  for (const auto& k : keys) {
    ++declarations[k.key];
    if (!k.section.empty()) full_keys.insert(k.section + "." + k.key);
  }
  for (const auto& [key, why] : AllowedBareKeys()) {
    EXPECT_TRUE(declarations.count(key)) << "allowed bare key '" << key << "' is no key any more: drop it";
  }

  const auto files = ScannedSources();
  ASSERT_GT(files.size(), 100u) << "the sources were not found under " << test::SourceDir();
  std::map<std::string, int> declared_in_sources;
  for (const auto& path : files) {
    const std::string text = test::ReadFile(path);
    const std::string where = std::filesystem::relative(path, test::SourceDir()).string();
    for (const Literal& l : StringLiterals(text)) {
      if (declarations.count(l.text)) {
        if (IsDeclaration(text, l.offset)) {
          ++declared_in_sources[l.text];
        } else {
          EXPECT_TRUE(AllowedBareKeys().count(l.text))
              << where << ":" << LineOf(text, l.offset) << ": the key \"" << l.text
              << "\" written again; name it through its declaration (KeyOf, app::ConfigKey)";
        }
      }
      const std::size_t end = l.text.find_first_of("=: ");
      const std::string head = l.text.substr(0, end);
      const bool names_a_key = end == std::string::npos || l.text[end] == '=' || l.text[end] == ':';
      EXPECT_FALSE(names_a_key && full_keys.count(head))
          << where << ":" << LineOf(text, l.offset) << ": \"" << l.text
          << "\" writes the key again; use app::ConfigKey or app::Override";
    }
  }
  for (const auto& [key, count] : declarations) {
    EXPECT_EQ(declared_in_sources[key], count)
        << "the key '" << key << "' is declared by " << count << " options struct(s) but appears as the "
        << "first argument of Field( / Enum( " << declared_in_sources[key] << " time(s) in the sources";
  }
}

TEST(OptionKeys, TheScannerFindsLiteralsAndSkipsCommentsAndCharacters) {
  const std::string code = R"cc(// "in a comment"
                                int n = 1'000;
                                char q = '"'; /* "in a block" */
                                v.Field("key_one", &a, "text");
                                auto s = std::string("map.visibility=") + R"x(raw "quoted")x";
  )cc";
  const auto literals = StringLiterals(code);
  ASSERT_EQ(literals.size(), 4u);
  EXPECT_EQ(literals[0].text, "key_one");
  EXPECT_TRUE(IsDeclaration(code, literals[0].offset));
  EXPECT_EQ(literals[1].text, "text");
  EXPECT_FALSE(IsDeclaration(code, literals[1].offset));
  EXPECT_EQ(literals[2].text, "map.visibility=");
  EXPECT_EQ(literals[3].text, "raw \"quoted\"");
}

// config/default.yaml against the declarations: the same sections and keys, in the same order, each with the
// default of its field (the byte-for-byte comparison in config_test.cc says that the file is stale; this
// one says which key).
TEST(OptionKeys, DefaultYamlHoldsEveryDeclaredKeyWithItsDefault) {
  const YAML::Node file = YAML::LoadFile((test::SourceDir() / "config" / "default.yaml").string());
  Config config;
  const auto sections = BindSections(config);
  ASSERT_EQ(file.size(), sections.size());
  for (const auto& section : sections) {
    const YAML::Node node = file[section.name];
    ASSERT_TRUE(node.IsMap()) << "config/default.yaml has no section " << section.name;
    std::vector<std::string> declared, written;
    for (const auto& f : section.binder.fields()) declared.push_back(f.key);
    for (const auto& kv : node) written.push_back(kv.first.as<std::string>());
    EXPECT_EQ(written, declared) << "keys of section " << section.name;
    for (const auto& f : section.binder.fields()) {
      if (!node[f.key]) continue;
      YAML::Emitter in_file, in_code;
      in_file << YAML::Flow << node[f.key];
      in_code << YAML::Flow << YAML::Load(YAML::Dump(f.dump()));
      EXPECT_EQ(std::string(in_file.c_str()), std::string(in_code.c_str())) << section.name << "." << f.key;
    }
  }
}

// A removed option (CHANGELOG.md, Removed) in a user's file or --set is an error naming it.
TEST(OptionKeys, ARemovedKeyIsAnErrorNamingIt) {
  const auto path = test::TempDir() / "old.yaml";
  std::ofstream(path) << "semantics:\n  enet_threads: 2\n";
  for (const auto& [file, overrides] : {std::pair<std::filesystem::path, std::vector<std::string>>{path, {}},
                                        {"", {"semantics.enet_threads=2"}}}) {
    try {
      LoadConfig(file, overrides);
      ADD_FAILURE() << "a removed key loaded";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("unknown config key 'semantics.enet_threads'"), std::string::npos)
          << e.what();
    }
  }
}

TEST(OptionKeys, ConfigKeyAndOverrideNameAMemberByItsDeclaration) {
  EXPECT_EQ(ConfigKey(&Config::map, &MapOptions::vote_window_frames), "map.vote_window_frames");
  EXPECT_EQ(ConfigKey(&Config::pose_input, &PoseInputOptions::poses), "input.poses");
  EXPECT_EQ(Override(&Config::output, &io::OutputOptions::dir, "out"), "output.dir=out");
  const Config c = LoadConfig("", {Override(&Config::map, &MapOptions::vote_window_frames, "4")});
  EXPECT_EQ(c.map.vote_window_frames, 4);
}

// Check()'s errors come from the declarations and keep the loader's form: section, key, requirement, value.
TEST(OptionKeys, OutOfRangeValuesAreNamedBySectionAndKey) {
  try {
    LoadConfig("", {"map.vote_window_frames=0"});
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "invalid config value map.vote_window_frames: must be >= 1 (got 0)");
  }
  try {
    LoadConfig("", {"depth.min_depth_m=5", "depth.max_depth_m=4"});
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "invalid config value depth.max_depth_m: must be greater than min_depth_m (got 4)");
  }
}

}  // namespace
}  // namespace semap::app
