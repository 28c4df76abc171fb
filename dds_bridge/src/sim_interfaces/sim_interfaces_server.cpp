#include "sim_interfaces/sim_interfaces_server.h"

#include <atomic>
#include <filesystem>
#include <thread>

#include "macsim/dds/wire.h"
#include "sim_interfaces/sim_interfaces_dispatch.h"
#include "simulation/simulation_dispatch.h"

namespace macsim {

namespace si = simulation_interfaces::msg::dds_;
namespace ss = simulation_interfaces::srv::dds_;
namespace rc = si::Result_Constants;
namespace st = si::SimulationState_Constants;
using sim_interfaces::result;

// The request and response types of a service, as ServiceServer takes them.
#define MACSIM_SERVICE(Name) ss::Name##_Request_PubSubType, ss::Name##_Response_PubSubType

template <class Req, class Resp>
void SimInterfacesServer::serve(const std::string& name, Respond<Req, Resp> respond) {
  using Server = dds::ServiceServer<Req, Resp>;
  // A request may come before the constructor returns: the handler waits for the server.
  auto slot = std::make_shared<std::atomic<Server*>>(nullptr);
  auto server = std::make_shared<Server>(
      participant_, kNamespace + name,
      [slot, respond](const typename Req::type& q, const dds::RequestId& id) {
        while (!slot->load()) std::this_thread::yield();
        respond(q, id, *slot->load());
      });
  slot->store(server.get());
  servers_.push_back(server);
}

template <class Req, class Resp, class Run>
void SimInterfacesServer::serve_on_world(const std::string& name, Run run) {
  using Server = dds::ServiceServer<Req, Resp>;
  using ReplyTo = std::pair<dds::RequestId, Server*>;
  using Queued = sim_interfaces::ServiceRequest<Req>;
  // On the simulation thread: the request run, answered where it came from.
  runner_.set_executor<Queued>([this, run](const Queued& q, const Command& c, World& world) {
    const auto response = run(q.message(), world);
    if (const auto* to = std::any_cast<ReplyTo>(&c.reply_to))
      to->second->reply(to->first, response);
    // Recorded when it changed the world: a service that can, answered RESULT_OK (a
    // set_simulation_state only when it stopped the simulation, which resets the world).
    constexpr bool kSetsState = std::is_same_v<Req, ss::SetSimulationState_Request_PubSubType>;
    return sim_interfaces::kChangesWorld<Req> && response.result().result() == rc::RESULT_OK &&
           (!kSetsState || stopped_);
  });
  forget_executors_.push_back([this] { runner_.set_executor<Queued>({}); });
  serve<Req, Resp>(
      name, [this, name](const typename Req::type& q, const dds::RequestId& id, Server& server) {
        Command c = request_command<Queued>(CommandSource::Ros2Service, q, name);
        c.reply_to = ReplyTo{id, &server};
        if (!runner_.push(std::move(c))) refuse_full(id, server);
      });
}

template <class Req, class Resp>
void SimInterfacesServer::refuse_full(const dds::RequestId& id,
                                      dds::ServiceServer<Req, Resp>& server) {
  typename Resp::type response;
  response.result(result(rc::RESULT_OPERATION_FAILED, runner_.queue_full_message()));
  server.reply(id, response);
}

template <class Req, class Resp>
void SimInterfacesServer::refuse(const std::string& name, const std::string& why) {
  serve<Req, Resp>(name, [why](const typename Req::type&, const dds::RequestId& id,
                               dds::ServiceServer<Req, Resp>& server) {
    typename Resp::type response;
    response.result(result(rc::RESULT_FEATURE_UNSUPPORTED, why));
    server.reply(id, response);
  });
}

SimInterfacesServer::SimInterfacesServer(dds::Participant& participant, Runner& runner,
                                         LoadLimits limits, std::function<void()> quit)
    : participant_(participant), runner_(runner), limits_(limits), quit_(std::move(quit)) {
  serve_entity_services();
  serve_simulation_state();
  serve_stepping();
  serve_world_loading();
  refuse_unsupported();
  simulate_steps_ = std::make_unique<SimulateStepsAction>(
      participant_, runner_, kNamespace + std::string("simulate_steps"));
}

/// The entities' and worlds' services, run on the world between steps (the features: at once).
void SimInterfacesServer::serve_entity_services() {
  namespace sim = sim_interfaces;
  // Constant, and its response has no result to say a full queue with: answered at once.
  serve<MACSIM_SERVICE(GetSimulatorFeatures)>(
      "get_simulator_features",
      [](const ss::GetSimulatorFeatures_Request_&, const dds::RequestId& id,
         dds::ServiceServer<MACSIM_SERVICE(GetSimulatorFeatures)>& server) {
        server.reply(id, sim::features());
      });
  serve_on_world<MACSIM_SERVICE(GetEntities)>("get_entities", sim::get_entities);
  serve_on_world<MACSIM_SERVICE(GetEntitiesStates)>("get_entities_states",
                                                    sim::get_entities_states);
  serve_on_world<MACSIM_SERVICE(GetEntityState)>("get_entity_state", sim::get_entity_state);
  serve_on_world<MACSIM_SERVICE(SetEntityState)>("set_entity_state", sim::set_entity_state);
  serve_on_world<MACSIM_SERVICE(GetEntityInfo)>("get_entity_info", sim::get_entity_info);
  serve_on_world<MACSIM_SERVICE(GetEntityBounds)>("get_entity_bounds", sim::get_entity_bounds);
  serve_on_world<MACSIM_SERVICE(SpawnEntity)>("spawn_entity", sim::spawn_entity);
  serve_on_world<MACSIM_SERVICE(SpawnEntities)>("spawn_entities", sim::spawn_entities);
  serve_on_world<MACSIM_SERVICE(DeleteEntity)>("delete_entity", sim::delete_entity);
  serve_on_world<MACSIM_SERVICE(GetSpawnables)>("get_spawnables", sim::get_spawnables);
  serve_on_world<MACSIM_SERVICE(GetCurrentWorld)>(
      "get_current_world", [](const ss::GetCurrentWorld_Request_&, World& world) {
        return sim::get_current_world(world);
      });
  serve_on_world<MACSIM_SERVICE(GetAvailableWorlds)>("get_available_worlds",
                                                     sim::get_available_worlds);
  serve_on_world<MACSIM_SERVICE(ResetSimulation)>(
      "reset_simulation", [this](const ss::ResetSimulation_Request_& q, World& world) {
        auto r = sim::reset_simulation(q, world);
        if (r.result().result() == rc::RESULT_OK) stopped_ = false;
        return r;
      });
}

/// Get and set the simulation's state: playing, paused, stopped (paused at the start), quitting.
void SimInterfacesServer::serve_simulation_state() {
  serve_on_world<MACSIM_SERVICE(GetSimulationState)>(
      "get_simulation_state", [this](const ss::GetSimulationState_Request_&, World&) {
        ss::GetSimulationState_Response_ r;
        if (!runner_.settings().paused) stopped_ = false;
        r.state().state(!runner_.settings().paused ? st::STATE_PLAYING
                        : stopped_                 ? st::STATE_STOPPED
                                                   : st::STATE_PAUSED);
        r.result(result(rc::RESULT_OK));
        return r;
      });

  serve_on_world<MACSIM_SERVICE(SetSimulationState)>(
      "set_simulation_state", [this](const ss::SetSimulationState_Request_& q, World& world) {
        namespace sc = ss::SetSimulationState_Response_Constants;
        ss::SetSimulationState_Response_ r;
        const bool paused = runner_.settings().paused;
        if (!paused) stopped_ = false;
        auto answer = [&r](uint8_t code, const std::string& message = "") {
          r.result(result(code, message));
          return r;
        };
        switch (q.state().state()) {
          case st::STATE_PLAYING:
            if (!paused) return answer(sc::ALREADY_IN_TARGET_STATE, "playing already");
            runner_.resume();
            stopped_ = false;
            return answer(rc::RESULT_OK);
          case st::STATE_PAUSED:
            if (paused && !stopped_) return answer(sc::ALREADY_IN_TARGET_STATE, "paused already");
            runner_.pause();  // from stopped: the start, paused
            stopped_ = false;
            return answer(rc::RESULT_OK);
          case st::STATE_STOPPED:
            if (paused && stopped_) return answer(sc::ALREADY_IN_TARGET_STATE, "stopped already");
            runner_.pause();
            world.reset(ResetScope::Everything);
            stopped_ = true;
            return answer(rc::RESULT_OK);
          case st::STATE_QUITTING:
            runner_.pause();
            if (quit_) quit_();
            return answer(rc::RESULT_OK);
          default:
            return answer(sc::INCORRECT_TRANSITION,
                          "state " + std::to_string(q.state().state()) +
                              " cannot be set: give STOPPED (0), PLAYING (1), PAUSED (2) or "
                              "QUITTING (3)");
        }
      });
}

/// StepSimulation, answered once its steps are done.
void SimInterfacesServer::serve_stepping() {
  // Answered once its steps are done: the request and where it came from, as a command.
  using StepServer = dds::ServiceServer<MACSIM_SERVICE(StepSimulation)>;
  using StepReplyTo = std::pair<dds::RequestId, StepServer*>;
  using StepCall = sim_interfaces::ServiceRequest<ss::StepSimulation_Request_PubSubType>;
  runner_.set_executor<StepCall>([this](const StepCall& call, const Command& c, World&) {
    const auto* to = std::any_cast<StepReplyTo>(&c.reply_to);
    if (!to) return false;
    const ss::StepSimulation_Request_& q = call.message();
    const dds::RequestId id = to->first;
    StepServer& server = *to->second;
    ss::StepSimulation_Response_ r;
    if (!runner_.settings().paused) {
      r.result(result(rc::RESULT_OPERATION_FAILED,
                      "the simulation is playing: pause it first (SetSimulationState)"));
      server.reply(id, r);
      return false;
    }
    stopped_ = false;
    if (q.steps() == 0) {
      r.result(result(rc::RESULT_OK));
      server.reply(id, r);
      return false;
    }
    const bool taken = runner_.request_steps(q.steps(), [id, &server](bool done) {
      ss::StepSimulation_Response_ stepped;
      stepped.result(done ? result(rc::RESULT_OK)
                          : result(rc::RESULT_OPERATION_FAILED,
                                   "cancelled: paused, or a body went unstable (see the "
                                   "events)"));
      server.reply(id, stepped);
    });
    if (!taken) {
      r.result(result(rc::RESULT_INCORRECT_STATE, "a step request is still running"));
      server.reply(id, r);
    }
    return false;
  });
  forget_executors_.push_back([this] { runner_.set_executor<StepCall>({}); });
  serve<MACSIM_SERVICE(StepSimulation)>(
      "step_simulation",
      [this](const ss::StepSimulation_Request_& q, const dds::RequestId& id, StepServer& server) {
        Command c = request_command<StepCall>(CommandSource::Ros2Service, q, "step_simulation");
        c.reply_to = StepReplyTo{id, &server};
        if (!runner_.push(std::move(c))) refuse_full(id, server);
      });
}

/// LoadWorld: parsed off the simulation thread, answered once the new world runs.
void SimInterfacesServer::serve_world_loading() {
  serve<MACSIM_SERVICE(LoadWorld)>(
      "load_world", [this](const ss::LoadWorld_Request_& q, const dds::RequestId& id,
                           dds::ServiceServer<MACSIM_SERVICE(LoadWorld)>& server) {
        namespace lc = ss::LoadWorld_Response_Constants;
        auto refuse_now = [&](uint8_t code, const std::string& message) {
          ss::LoadWorld_Response_ r;
          r.result(result(code, message));
          server.reply(id, r);
        };
        const std::string file = sim_interfaces::uri_path(q.uri());
        if (file.empty() && q.resource_string().empty()) {
          return refuse_now(lc::NO_RESOURCE, "give uri (a <WORLD> file) or resource_string");
        }
        if (!file.empty() && !runner_.data_roots().contains(file)) {  // said before anything else
          return refuse_now(lc::RESOURCE_PARSE_ERROR, DataRoots::outside_message(file));
        }
        if (!file.empty() && std::filesystem::path(file).extension() != ".xml") {
          return refuse_now(lc::UNSUPPORTED_FORMAT, "'" + q.uri() + "' is no macsim_xml file");
        }
        // Parsed off the simulation thread; answered once the new world runs (or was refused).
        const LoadQueued queued = queue_world_load(
            runner_, limits_, {file, q.resource_string()},
            [this, id, &server](const LoadOutcome& outcome) {
              ss::LoadWorld_Response_ r;
              if (outcome.ok) {
                runner_.pause();  // a loaded world is left stopped
                stopped_ = true;
                r.world(sim_interfaces::get_current_world(runner_.world()).world());
                r.result(result(rc::RESULT_OK));
              } else {
                r.result(result(outcome.code == ErrorCode::BadFile ? lc::RESOURCE_PARSE_ERROR
                                                                   : rc::RESULT_OPERATION_FAILED,
                                outcome.error));
              }
              server.reply(id, r);
            });
        if (queued == LoadQueued::LoadRunning) {
          refuse_now(rc::RESULT_OPERATION_FAILED, "a world load is still running");
        } else if (queued == LoadQueued::QueueFull) {
          refuse_now(rc::RESULT_OPERATION_FAILED, runner_.queue_full_message());
        }
      });
}

/// The services this simulator has no use for, refused saying why.
void SimInterfacesServer::refuse_unsupported() {
  refuse<MACSIM_SERVICE(UnloadWorld)>("unload_world",
                                      "a macsim always runs a world: LoadWorld replaces it");
  refuse<MACSIM_SERVICE(SetEntityInfo)>(
      "set_entity_info",
      "category and tags follow from the object's description (portable or fixed, kind, "
      "magnetizable, user data); the supervisor (macsim_msgs) changes those");
  refuse<MACSIM_SERVICE(GetNamedPoses)>("get_named_poses",
                                        "world files of this simulator name no poses");
  refuse<MACSIM_SERVICE(GetNamedPoseBounds)>("get_named_pose_bounds",
                                             "world files of this simulator name no poses");
}

SimInterfacesServer::~SimInterfacesServer() {
  simulate_steps_.reset();
  servers_.clear();
  for (const auto& forget : forget_executors_) forget();  // what is still queued runs nowhere
}

std::vector<std::string> SimInterfacesServer::service_names() {
  std::vector<std::string> names;
  for (const char* s : {"get_simulator_features GetSimulatorFeatures",
                        "get_simulation_state GetSimulationState",
                        "set_simulation_state SetSimulationState",
                        "step_simulation StepSimulation",
                        "reset_simulation ResetSimulation",
                        "load_world LoadWorld",
                        "unload_world UnloadWorld",
                        "get_current_world GetCurrentWorld",
                        "get_available_worlds GetAvailableWorlds",
                        "get_entities GetEntities",
                        "get_entities_states GetEntitiesStates",
                        "get_entity_state GetEntityState",
                        "set_entity_state SetEntityState",
                        "get_entity_info GetEntityInfo",
                        "set_entity_info SetEntityInfo",
                        "get_entity_bounds GetEntityBounds",
                        "spawn_entity SpawnEntity",
                        "spawn_entities SpawnEntities",
                        "delete_entity DeleteEntity",
                        "get_spawnables GetSpawnables",
                        "get_named_poses GetNamedPoses",
                        "get_named_pose_bounds GetNamedPoseBounds"}) {
    const std::string line = s;
    const auto space = line.find(' ');
    names.push_back(std::string(kNamespace) + line.substr(0, space) +
                    " (simulation_interfaces/srv/" + line.substr(space + 1) + ", ROS 2 service)");
  }
  names.push_back(std::string(kNamespace) +
                  "simulate_steps (simulation_interfaces/action/SimulateSteps, ROS 2 action)");
  return names;
}

#undef MACSIM_SERVICE

}  // namespace macsim
