// The main of every test binary: GoogleTest's flags and its help (--help, -h), and an unknown
// argument refused (exit 2) instead of running the whole suite as if it had not been given.
#include <gtest/gtest.h>

#include <iostream>
#include <string>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);  // takes out the --gtest_* flags it knows
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h" || arg == "-?" || arg == "/?") {
      return RUN_ALL_TESTS();  // GoogleTest printed its help and runs nothing: exit 0
    }
  }
  if (argc > 1) {
    std::cerr << argv[0] << ": unknown argument '" << argv[1] << "' (GoogleTest's flags: --help)\n";
    return 2;
  }
  return RUN_ALL_TESTS();
}
