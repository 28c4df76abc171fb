// macsim_shm_clean: removes the Fast DDS shared-memory files that killed participants left in
// /dev/shm (this user's, unused by any live process, older than --min-age seconds).
#include <iostream>

#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"
#include "macsim/dds/shared_memory.h"

int main(int argc, char** argv) {
  macsim::dds::CommandLine cli(
      "macsim_shm_clean",
      "Removes Fast DDS shared-memory files left by killed participants (files of this user "
      "that no live process maps or holds open). Shared memory belongs to no DDS domain: "
      "--domain and --profile are accepted and change nothing.");
  macsim::dds::ParticipantOptions participant{0, "", "macsim_shm_clean"};
  cli.participant_options(&participant);
  bool dry_run = false, verbose = false;
  int min_age = 2;
  cli.flag("dry-run", "list what would be removed, remove nothing", &dry_run);
  cli.flag("verbose", "name every file removed", &verbose);
  cli.option("min-age", "SECONDS", "leave younger files alone (default 2)", &min_age);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (min_age < 0) {
    macsim::log::error("macsim_shm_clean: --min-age must not be negative");
    return 2;
  }
  const auto result =
      macsim::dds::clean_stale_shared_memory(std::chrono::seconds(min_age), dry_run);
  if (verbose) {
    for (const auto& name : result.removed) std::cout << "  " << name << "\n";
  }
  std::cout << "macsim_shm_clean: " << (dry_run ? "would remove " : "removed ")
            << result.removed.size() << " stale files, " << result.in_use << " in use\n";
  return 0;
}
