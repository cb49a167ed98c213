// Test support for `semap view`: starting it in the background, and loading its page in headless Chromium
// (tests/tools/view/page_check.mjs, playwright-core from tools/view/web's lock file, Debian's chromium).
#pragma once

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <thread>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::test {

// What headless Chromium needs and is missing ("" if nothing): node, /usr/bin/chromium (or $SEMAP_CHROMIUM),
// playwright-core installed in tools/view/web/node_modules (scripts/setup runs `npm ci` there).
inline std::string BrowserMissing() {
  std::string missing;
  if (RunShell("command -v node").exit_code != 0) missing += " node";
  const char* chromium = std::getenv("SEMAP_CHROMIUM");
  if (!std::filesystem::exists(chromium != nullptr ? chromium : "/usr/bin/chromium")) missing += " chromium";
  if (!std::filesystem::exists(SourceDir() / "tools/view/web/node_modules/playwright-core/package.json")) {
    missing += " playwright-core (npm ci in tools/view/web)";
  }
  return missing;
}

// The page_check.mjs command line (without the expectation options); `url` goes in double quotes (a shell
// variable may name it).
inline std::string PageCheckCommand(const std::string& url, const std::filesystem::path& dir) {
  return "node " + (SourceDir() / "tests/tools/view/page_check.mjs").string() + " --url \"" + url +
         "\" --web-dir " + (SourceDir() / "tools/view/web").string() + " --screenshot " +
         (dir / "page.png").string() + " --view-screenshot " + (dir / "view.png").string();
}

// The JSON line page_check.mjs printed (last line of its output), or null.
inline nlohmann::json PageReport(const std::string& output) {
  const auto end = output.find_last_not_of('\n');
  if (end == std::string::npos) return nullptr;
  const auto begin = output.rfind('\n', end);
  return nlohmann::json::parse(output.substr(begin == std::string::npos ? 0 : begin + 1, end + 1), nullptr,
                               /*allow_exceptions=*/false);
}

// The page's background colour (tools/view/web/src/main.js BACKGROUND), BGR as OpenCV reads it.
inline const cv::Vec3b kViewBackground{0x30, 0x22, 0x1e};

// Share of the screenshot's pixels that differ from the background by more than `tolerance` in a channel.
inline double ShareNotBackground(const std::filesystem::path& png, int tolerance = 12) {
  const cv::Mat image = cv::imread(png.string(), cv::IMREAD_COLOR);
  if (image.empty()) return -1.0;
  std::int64_t differ = 0;
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      const cv::Vec3b p = image.at<cv::Vec3b>(r, c);
      for (int k = 0; k < 3; ++k) {
        if (std::abs(int(p[k]) - int(kViewBackground[k])) > tolerance) {
          ++differ;
          break;
        }
      }
    }
  }
  return double(differ) / double(image.total());
}

// The face count of a PLY file's header ("element face N"), read without semap's PLY reader; -1 if absent.
inline std::int64_t PlyHeaderFaces(const std::filesystem::path& ply) {
  std::ifstream in(ply, std::ios::binary);
  std::string line;
  while (std::getline(in, line) && line != "end_header") {
    if (line.rfind("element face ", 0) == 0) return std::stoll(line.substr(13));
  }
  return -1;
}

// `semap view ARGS` in the background, its output in `log`; the URL it printed (waits up to 20 s; "" if
// none).
struct BackgroundView {
  int pid = -1;
  std::string url;
  std::filesystem::path log;
  BackgroundView(const std::string& args, const std::filesystem::path& log_path) : log(log_path) {
    const auto r =
        RunShell(std::string(SEMAP_EXE) + " view " + args + " > " + log.string() + " 2>&1 & echo $!");
    pid = std::stoi(r.output);
    for (int i = 0; i < 200 && url.empty(); ++i) {
      std::ifstream in(log);
      std::string line;
      while (std::getline(in, line)) {
        if (line.rfind("http://", 0) == 0) url = line;
      }
      if (url.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  ~BackgroundView() {
    if (pid > 0) kill(pid, SIGTERM);
  }
  std::string Log() const { return test::ReadFile(log); }
};

}  // namespace semap::test

// At the start of a test that loads the page: skipped without the browser, failed under CI (CI=true).
#define SEMAP_REQUIRE_BROWSER()                                                                      \
  do {                                                                                               \
    const std::string semap_browser_missing_ = ::semap::test::BrowserMissing();                      \
    if (!semap_browser_missing_.empty()) {                                                           \
      if (::semap::test::UnderCi())                                                                  \
        FAIL() << "missing under CI:" << semap_browser_missing_ << " (scripts/setup installs them)"; \
      GTEST_SKIP() << "needs" << semap_browser_missing_;                                             \
    }                                                                                                \
  } while (false)
