// Replays files through a fuzz target's LLVMFuzzerTestOneInput without libFuzzer (the
// normal build's ctest tests fuzz.replay.<target>): every regular file of every
// directory argument (names starting with '.' skipped), and every file argument, in
// sorted order. A crash, sanitizer report or finding of the target fails the test;
// a missing directory is skipped (fuzz/regressions/<target>/ exists only once a
// finding has been kept). No input at all is an error (a wrong path).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const fs::path p(argv[i]);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<fs::path> here;
      for (const fs::directory_entry& e : fs::directory_iterator(p, ec)) {
        const std::string name = e.path().filename().string();
        if (!name.empty() && name[0] != '.' && e.is_regular_file(ec)) here.push_back(e.path());
      }
      std::sort(here.begin(), here.end());
      std::printf("fuzz replay: %s: %zu inputs\n", argv[i], here.size());
      files.insert(files.end(), here.begin(), here.end());
    } else if (fs::is_regular_file(p, ec)) {
      files.push_back(p);
    } else {
      std::printf("fuzz replay: %s: no such directory or file, skipped\n", argv[i]);
    }
  }
  if (files.empty()) {
    std::fprintf(stderr, "fuzz replay: no inputs (usage: %s DIR_OR_FILE...)\n", argv[0]);
    return 2;
  }
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "fuzz replay: cannot read %s\n", f.c_str());
      return 2;
    }
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::printf("fuzz replay: running %s (%zu bytes)\n", f.c_str(), bytes.size());
    std::fflush(stdout);
    const uint8_t empty = 0;
    LLVMFuzzerTestOneInput(bytes.empty() ? &empty : bytes.data(), bytes.size());
  }
  std::printf("fuzz replay: %zu inputs ran without a finding\n", files.size());
  return 0;
}
