// compare.csv as `semap compare` writes it, read back by the tests (test helper).
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace semap::test {

// Each row by its method (the quoted first column), as header cell → cell text, as written.
inline std::map<std::string, std::map<std::string, std::string>> CompareCsvCells(
    const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string h; std::getline(hs, h, ',');) header.push_back(h);
  std::map<std::string, std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const auto close = line.find('"', 1);
    const std::string method = line.substr(1, close - 1);
    std::stringstream vs(line.substr(close + 2));
    std::size_t column = 1;
    for (std::string v; std::getline(vs, v, ','); ++column) rows[method][header.at(column)] = v;
  }
  return rows;
}

}  // namespace semap::test
