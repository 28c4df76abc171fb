// interfaceTest: the seed's example, as a DDS client. `interfaceTest -load WORLD` asks the running
// simulator to load a world, then prints what it holds.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "macsim/client/supervisor_client.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"

namespace mm = macsim_msgs::msg::dds_;
using macsim::client::SimulationClient;
using macsim::client::SupervisorClient;

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{0, "", "interfaceTest"};
  std::string world;
  macsim::dds::CommandLine cli(
      "interfaceTest",
      "Asks the running simulator to load a world (as MACSim's "
      "interfaceTest -load did), then lists its objects and doors.\n"
      "Exit 0: loaded; 1: the simulator refused; 2: usage, or no simulator.");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("load", "WORLD", "world file to load (a path the simulator can read)", &world);
  if (auto code = cli.parse(argc, argv)) return *code;
  try {
    macsim::dds::Participant dds(participant);
    SimulationClient simulation(dds);
    SupervisorClient supervisor(dds);
    if (!simulation.wait_for_server(std::chrono::seconds(15))) {
      macsim::log::error("interfaceTest: no simulator on DDS domain {}", participant.domain);
      return 2;
    }
    if (!world.empty()) {
      auto load = SimulationClient::request(mm::SIM_LOAD_WORLD);
      load.world_file(std::filesystem::absolute(world).string());
      const auto reply = simulation.call(load);
      if (!reply || reply->code() != mm::ERR_OK) {
        macsim::log::error(
            "interfaceTest: the simulator did not load '{}': {}", world,
            reply ? reply->message()
                  : macsim::client::describe(simulation.last_outcome(), "simulation control",
                                             participant.domain));
        return 1;
      }
      std::printf("interfaceTest: loaded %s\n", world.c_str());
    }
    const auto objects = supervisor.call(macsim::client::supervisor::list_objects());
    const auto doors = supervisor.call(macsim::client::supervisor::door_count());
    if (!objects || !doors) {
      macsim::log::error("interfaceTest: the supervisor did not answer");
      return 2;
    }
    std::printf("interfaceTest: %d objects, %d doors\n", objects->count(), doors->count());
    for (std::size_t i = 0; i < objects->names().size(); ++i) {
      std::printf("  [%zu] id %u  %s\n", i, objects->object_ids()[i], objects->names()[i].c_str());
    }
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("interfaceTest: DDS error: {}", e.what());
    return 2;
  }
  return 0;
}
