// `--domain N` of the benchmarks that run one simulator per layout: the first of the DDS domains
// they use, one per run, so that two benchmarks side by side can be kept apart.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace macsim::bench {

/// How many domains from the first a layout benchmark uses.
inline constexpr int kLayoutDomains = 80;
/// The first of them by default: 10-89, below the tests' 100-232 (tests/support/test_domain.cpp),
/// so that a benchmark run beside the test suite never shares a domain with a test.
inline constexpr int kLayoutDomainBase = 10;

/// `--domain N` taken out of `args` (the first domain, 0-152: Fast DDS's ports reach to domain
/// 232), or `fallback` without it; nullopt, with a message naming `program`, when N is no such
/// number.
inline std::optional<int> take_domain_base(std::vector<std::string>& args, const char* program,
                                           int fallback) {
  for (std::size_t k = 0; k < args.size(); ++k) {
    if (args[k] != "--domain") continue;
    const std::string value = k + 1 < args.size() ? args[k + 1] : "";
    char* end = nullptr;
    const long n = std::strtol(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || n < 0 || n > 232 - kLayoutDomains) {
      std::fprintf(stderr,
                   "%s: --domain takes the first of the %d domains it uses, 0-%d, not '%s'\n",
                   program, kLayoutDomains, 232 - kLayoutDomains, value.c_str());
      return std::nullopt;
    }
    args.erase(args.begin() + static_cast<std::ptrdiff_t>(k),
               args.begin() + static_cast<std::ptrdiff_t>(std::min(k + 2, args.size())));
    return static_cast<int>(n);
  }
  return fallback;
}

}  // namespace macsim::bench
