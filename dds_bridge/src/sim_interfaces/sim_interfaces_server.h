// The ROS 2 standard simulator API (simulation_interfaces, Jazzy) served as ROS 2 services, as
// rmw_fastrtps_cpp carries them, under /macsim/<service> (e.g. /macsim/step_simulation).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "macsim/dds/ros2_service.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_loader.h"
#include "sim_interfaces/simulate_steps_action.h"

namespace macsim {

/// Serves the 22 services of simulation_interfaces and its action SimulateSteps: each request
/// runs on the simulation thread between two steps; a step request is answered once its steps
/// are done, a load once the new world runs; the four this simulator has no use for answer
/// RESULT_FEATURE_UNSUPPORTED.
class SimInterfacesServer {
 public:
  /// Worlds loaded on request are held to `limits`; `quit` ends macsim (STATE_QUITTING).
  SimInterfacesServer(dds::Participant& participant, Runner& runner, LoadLimits limits,
                      std::function<void()> quit);
  ~SimInterfacesServer();

  /// The namespace of the services.
  static constexpr const char* kNamespace = "/macsim/";
  /// The services' names and types, for the start-up banner.
  static std::vector<std::string> service_names();

 private:
  void serve_entity_services();
  void serve_simulation_state();
  void serve_stepping();
  void serve_world_loading();
  void refuse_unsupported();
  template <class Req, class Resp>
  using Respond = std::function<void(const typename Req::type&, const dds::RequestId&,
                                     dds::ServiceServer<Req, Resp>&)>;
  /// Serves one service; `respond` runs on Fast DDS's thread.
  template <class Req, class Resp>
  void serve(const std::string& name, Respond<Req, Resp> respond);
  /// Serves one service whose requests `run(request, world)` answers on the simulation thread.
  template <class Req, class Resp, class Run>
  void serve_on_world(const std::string& name, Run run);
  /// Serves one service with a refusal: RESULT_FEATURE_UNSUPPORTED and why.
  template <class Req, class Resp>
  void refuse(const std::string& name, const std::string& why);
  /// Answers a request the runner's full queue refused: RESULT_OPERATION_FAILED, saying so.
  template <class Req, class Resp>
  void refuse_full(const dds::RequestId& id, dds::ServiceServer<Req, Resp>& server);

  dds::Participant& participant_;
  Runner& runner_;
  const LoadLimits limits_;
  std::function<void()> quit_;
  bool stopped_ = false;  // STATE_STOPPED: paused at the start (simulation thread only)
  std::vector<std::shared_ptr<void>> servers_;
  /// Each takes the runner's executor of one service's requests away (the destructor runs them).
  std::vector<std::function<void()>> forget_executors_;
  std::unique_ptr<SimulateStepsAction> simulate_steps_;  // progress and cancel of steps
};

}  // namespace macsim
