// The user documentation holds together: every relative link in README.md, CHANGELOG.md, docs/*.md,
// bench/RESULTS.md and bench/results/*.md names a file that exists (and, with #anchor, a heading of it), and
// every `semap` command written in README.md and docs/*.md names a subcommand and options that the built
// executable's
// --help knows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;

struct Located {
  int line = 0;  // 1-based line of the markdown file
  std::string text;
};

// The text of a markdown file without its code: fenced blocks and inline code spans become blanks (lines are
// kept, so that line numbers stay right). Indented code blocks are rare in these files, but they hold the
// commands, not links, so they are blanked as well.
std::string WithoutCode(const std::string& markdown) {
  std::istringstream in(markdown);
  std::string line, out;
  bool fenced = false;
  while (std::getline(in, line)) {
    const bool fence = line.rfind("```", 0) == 0;
    if (fence) fenced = !fenced;
    if (fence || fenced || line.rfind("    ", 0) == 0) {
      out += "\n";
      continue;
    }
    out += std::regex_replace(line, std::regex("`[^`]*`"), "``") + "\n";
  }
  return out;
}

int LineOf(const std::string& text, size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(offset), '\n'));
}

// Link targets: [text](target), ![alt](target "title"), [label]: target, <img src="target">.
std::vector<Located> LinkTargets(const std::string& markdown) {
  const std::string text = WithoutCode(markdown);
  std::vector<Located> targets;
  static const std::regex patterns[] = {
      std::regex(R"re(\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\))re"),
      std::regex(R"re((?:^|\n)\s{0,3}\[[^\]\n]+\]:\s*<?([^\s>]+))re"),
      std::regex(R"re(<img\s[^>]*src="([^"]+)")re"),
  };
  for (const auto& re : patterns) {
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it) {
      const auto& m = *it;
      targets.push_back({LineOf(text, static_cast<size_t>(m.position(1))), m[1].str()});
    }
  }
  return targets;
}

// GitHub's anchor of a heading: lower case, spaces to '-', punctuation and symbols dropped (letters, digits,
// '-' and '_' kept; of the non-ASCII characters, Latin and Greek letters kept).
std::string Slug(const std::string& heading) {
  std::string slug;
  for (size_t i = 0; i < heading.size();) {
    const auto c = static_cast<unsigned char>(heading[i]);
    if (c < 0x80) {
      if (std::isalnum(c) || c == '-' || c == '_') slug += static_cast<char>(std::tolower(c));
      if (c == ' ') slug += '-';
      ++i;
      continue;
    }
    const size_t len = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : 2;
    unsigned cp = c & (len == 2 ? 0x1F : len == 3 ? 0x0F : 0x07);
    for (size_t k = 1; k < len && i + k < heading.size(); ++k) cp = (cp << 6) | (heading[i + k] & 0x3F);
    const bool letter =
        (cp >= 0xC0 && cp <= 0x24F && cp != 0xD7 && cp != 0xF7) || (cp >= 0x370 && cp <= 0x3FF);
    if (letter) slug += heading.substr(i, len);
    i += len;
  }
  return slug;
}

std::set<std::string> Anchors(const std::string& markdown) {
  std::set<std::string> anchors;
  std::map<std::string, int> seen;
  std::istringstream in(markdown);
  std::string line;
  bool fenced = false;
  static const std::regex heading(R"re(^#{1,6}\s+(.*?)\s*#*\s*$)re");
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) fenced = !fenced;
    std::smatch m;
    if (fenced || !std::regex_match(line, m, heading)) continue;
    const std::string slug = Slug(m[1].str());
    const int n = seen[slug]++;
    anchors.insert(n == 0 ? slug : slug + "-" + std::to_string(n));
  }
  return anchors;
}

// The broken links of one markdown file: "file:line: target (why)".
std::vector<std::string> BrokenLinks(const fs::path& file, const std::string& markdown) {
  std::vector<std::string> broken;
  static const std::regex scheme(R"re(^[A-Za-z][A-Za-z0-9+.-]*:)re");
  for (const auto& [line, target] : LinkTargets(markdown)) {
    if (std::regex_search(target, scheme)) continue;  // http:, https:, mailto:
    const size_t hash = target.find('#');
    const std::string path = target.substr(0, hash);
    const std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
    const fs::path resolved = path.empty() ? file : (file.parent_path() / path).lexically_normal();
    const std::string where = file.filename().string() + ":" + std::to_string(line) + ": " + target;
    if (!fs::exists(resolved)) {
      broken.push_back(where + " (no such file: " + resolved.string() + ")");
    } else if (!anchor.empty() && resolved.extension() == ".md") {
      const std::string text = path.empty() ? markdown : test::ReadFile(resolved);
      if (Anchors(text).count(anchor) == 0) broken.push_back(where + " (no heading with that anchor)");
    }
  }
  return broken;
}

// `semap` commands: the lines of code blocks (fenced, or indented by four spaces) and the inline code spans
// that start with `semap ` (or build/tools/semap, after taskset / nice), continuation lines joined, shell
// comments cut.
std::vector<Located> SemapCommands(const std::string& markdown) {
  std::vector<Located> commands;
  std::istringstream in(markdown);
  std::string line;
  bool fenced = false;
  int number = 0;
  static const std::regex start(
      R"re(^(?:(?:taskset -c \S+|nice -n \d+|\S+=\S+)\s+)*(?:\.?/?build/tools/)?semap\s)re");
  static const std::regex span("`([^`]*)`");
  std::string pending;
  int pending_line = 0;
  while (std::getline(in, line)) {
    ++number;
    const bool fence = line.rfind("```", 0) == 0;
    if (fence) {
      fenced = !fenced;
      continue;
    }
    if (fenced || line.rfind("    ", 0) == 0) {
      std::string code = line.substr(
          line.find_first_not_of(' ') == std::string::npos ? line.size() : line.find_first_not_of(' '));
      if (pending.empty()) pending_line = number;
      const size_t comment = code.find(" #");
      if (comment != std::string::npos) code.resize(comment);
      if (!code.empty() && code.back() == '\\') {
        pending += code.substr(0, code.size() - 1) + " ";
        continue;
      }
      code = pending + code;
      pending.clear();
      if (std::regex_search(code, start)) commands.push_back({pending_line, code});
      continue;
    }
    pending.clear();
    for (auto it = std::sregex_iterator(line.begin(), line.end(), span); it != std::sregex_iterator(); ++it) {
      const std::string code = (*it)[1].str() + " ";
      if (std::regex_search(code, start)) commands.push_back({number, code});
    }
  }
  return commands;
}

struct HelpText {
  std::set<std::string> subcommands;
  std::set<std::string> root_options;
  std::map<std::string, std::set<std::string>> options;  // of each subcommand
};

std::set<std::string> LongOptions(const std::string& help) {
  std::set<std::string> options;
  static const std::regex re("--[A-Za-z0-9][A-Za-z0-9-]*");
  for (auto it = std::sregex_iterator(help.begin(), help.end(), re); it != std::sregex_iterator(); ++it) {
    options.insert(it->str());
  }
  return options;
}

// The subcommands listed by `semap --help` (the first word of each line under "Subcommands:").
std::set<std::string> Subcommands(const std::string& help) {
  std::set<std::string> subs;
  std::istringstream in(help);
  std::string line;
  bool listing = false;
  static const std::regex item(R"re(^\s+([a-z][a-z0-9-]*)\b.*)re");
  while (std::getline(in, line)) {
    std::string lower = line;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (lower.rfind("subcommands:", 0) == 0) {
      listing = true;
      continue;
    }
    std::smatch m;
    if (listing && std::regex_match(line, m, item)) {
      subs.insert(m[1].str());
    } else if (listing && !line.empty() && line[0] != ' ') {
      listing = false;
    }
  }
  return subs;
}

// What is wrong with one command: an unknown subcommand or option ("" when nothing).
std::vector<std::string> UnknownWords(const std::string& command, const HelpText& help) {
  std::vector<std::string> unknown;
  std::istringstream in(command);
  std::string word;
  std::vector<std::string> words;
  while (in >> word) words.push_back(word);
  auto semap = std::find_if(words.begin(), words.end(), [](const std::string& w) {
    return w == "semap" || (w.size() > 6 && w.compare(w.size() - 6, 6, "/semap") == 0);
  });
  if (semap == words.end() || semap + 1 == words.end()) return unknown;
  std::string sub = *(semap + 1);
  const bool root = sub[0] == '-';
  // A placeholder (`semap <cmd> --help`), or a message quoted from the program (`semap view: port ...`).
  if (!root && (sub.find_first_of("<>") != std::string::npos || sub == "SUB" || sub.back() == ':'))
    return unknown;
  if (!root && help.subcommands.count(sub) == 0) {
    unknown.push_back("subcommand '" + sub + "'");
    return unknown;
  }
  const std::set<std::string>& known = root ? help.root_options : help.options.at(sub);
  static const std::regex option("^(--[A-Za-z0-9][A-Za-z0-9-]*)");
  for (auto it = root ? semap + 1 : semap + 2; it != words.end(); ++it) {
    std::smatch m;
    if (!std::regex_search(*it, m, option)) continue;
    if (known.count(m[1].str()) == 0)
      unknown.push_back("option '" + m[1].str() + "' of semap " + (root ? "" : sub));
  }
  return unknown;
}

const HelpText& SemapHelp() {
  static const HelpText help = [] {
    HelpText h;
    const auto root = test::RunSemap("--help");
    EXPECT_EQ(root.exit_code, 0) << root.output;
    h.subcommands = Subcommands(root.output);
    h.root_options = LongOptions(root.output);
    for (const auto& sub : h.subcommands) {
      const auto r = test::RunSemap(sub + " --help");
      EXPECT_EQ(r.exit_code, 0) << sub << ": " << r.output;
      h.options[sub] = LongOptions(r.output);
    }
    return h;
  }();
  return help;
}

// The .md files of one directory, sorted.
std::vector<fs::path> MarkdownIn(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".md") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// README.md and docs/*.md; with the results, also CHANGELOG.md, bench/RESULTS.md and its history files.
std::vector<fs::path> DocFiles(bool with_results) {
  const fs::path root = test::SourceDir();
  std::vector<fs::path> files{root / "README.md"};
  if (with_results) {
    files.push_back(root / "CHANGELOG.md");
    files.push_back(root / "bench" / "RESULTS.md");
    const auto history = MarkdownIn(root / "bench" / "results");
    files.insert(files.end(), history.begin(), history.end());
  }
  const auto docs = MarkdownIn(root / "docs");
  files.insert(files.end(), docs.begin(), docs.end());
  return files;
}

void WriteText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string Joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += "  " + l + "\n";
  return out;
}

// The checker itself finds what it must (so that a passing run means something).
TEST(DocsCheck, FindsABrokenLinkAndAMissingAnchor) {
  const fs::path dir = test::TempDir();
  WriteText(dir / "there.md", "# A heading, with punctuation (and `code`)\n");
  const std::string md =
      "# Title\n[ok](there.md) [ok](there.md#a-heading-with-punctuation-and-code) [ok](#title)\n"
      "![pic](missing.png)\n[no anchor](there.md#nowhere)\n`[in code](nowhere.md)`\n"
      "    [in a code block](nowhere.md)\n[web](https://example.com/x)\n";
  WriteText(dir / "page.md", md);
  const auto broken = BrokenLinks(dir / "page.md", md);
  ASSERT_EQ(broken.size(), 2u) << Joined(broken);
  EXPECT_NE(broken[0].find("page.md:3: missing.png (no such file"), std::string::npos) << broken[0];
  EXPECT_NE(broken[1].find("page.md:4: there.md#nowhere (no heading"), std::string::npos) << broken[1];
}

TEST(DocsCheck, FindsAnUnknownSubcommandAndOption) {
  const std::string md =
      "    semap run seq --method PS --out run     # a comment --not-an-option\n"
      "    taskset -c 0,1 semap table a=b \\\n      --frobnicate 3\n"
      "Inline: `semap evaluate seq` and `semap run seq --eval` and `semap <cmd> --help`.\n";
  const auto commands = SemapCommands(md);
  ASSERT_EQ(commands.size(), 5u);
  EXPECT_EQ(commands[1].line, 2);
  HelpText help;
  help.subcommands = {"run", "table"};
  help.options["run"] = {"--method", "--out", "--eval", "--help"};
  help.options["table"] = {"--out", "--help"};
  EXPECT_TRUE(UnknownWords(commands[0].text, help).empty());
  EXPECT_EQ(UnknownWords(commands[1].text, help),
            std::vector<std::string>{"option '--frobnicate' of semap table"});
  EXPECT_EQ(UnknownWords(commands[2].text, help), std::vector<std::string>{"subcommand 'evaluate'"});
  EXPECT_TRUE(UnknownWords(commands[3].text, help).empty());
  EXPECT_TRUE(UnknownWords(commands[4].text, help).empty());
}

TEST(Docs, EveryRelativeLinkResolves) {
  std::vector<std::string> broken;
  size_t links = 0;
  for (const auto& file : DocFiles(true)) {
    ASSERT_TRUE(fs::exists(file)) << file;
    const std::string md = test::ReadFile(file);
    links += LinkTargets(md).size();
    const auto b = BrokenLinks(file, md);
    broken.insert(broken.end(), b.begin(), b.end());
  }
  EXPECT_GT(links, 10u);
  EXPECT_TRUE(broken.empty()) << broken.size() << " broken link(s):\n" << Joined(broken);
}

TEST(Docs, CommandsNameSubcommandsAndOptionsThatSemapKnows) {
  const HelpText& help = SemapHelp();
  ASSERT_GE(help.subcommands.size(), 10u) << "semap --help lists too few subcommands";
  ASSERT_TRUE(help.subcommands.count("run"));
  ASSERT_TRUE(help.options.at("run").count("--method"));
  std::vector<std::string> unknown;
  size_t readme_commands = 0;
  for (const auto& file : DocFiles(false)) {
    const auto commands = SemapCommands(test::ReadFile(file));
    if (file.filename() == "README.md") readme_commands = commands.size();
    for (const auto& [line, command] : commands) {
      for (const auto& u : UnknownWords(command, help)) {
        unknown.push_back(file.filename().string() + ":" + std::to_string(line) + ": " + u +
                          " in: " + command);
      }
    }
  }
  EXPECT_GE(readme_commands, 10u) << "README.md: too few semap commands found";
  EXPECT_TRUE(unknown.empty()) << unknown.size() << " unknown word(s):\n" << Joined(unknown);
}

}  // namespace
}  // namespace semap::tools
