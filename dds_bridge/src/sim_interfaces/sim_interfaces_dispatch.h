// The ROS 2 simulation_interfaces requests that concern the world alone, run against it: one
// function per service, the response out. No DDS here: SimInterfacesServer calls them on the
// simulation thread; unit tests call them directly. Entities are the world's objects (by their
// unique names) and its robots (by theirs).
#pragma once

#include <memory>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "macsim/msg/simulation_interfacesPubSubTypes.h"
#include "macsim/sim_core/command.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world.h"
#include "typed_request.h"

namespace macsim::sim_interfaces {

namespace si = simulation_interfaces::msg::dds_;
namespace ss = simulation_interfaces::srv::dds_;

/// The file a URI names: "file://" taken off, anything else taken as a path.
std::string uri_path(const std::string& uri);

/// A Result with that code and message.
si::Result_ result(uint8_t code, const std::string& message = "");

/// What this simulator serves (features, spawn formats, notes on entities).
ss::GetSimulatorFeatures_Response_ features();

ss::GetEntities_Response_ get_entities(const ss::GetEntities_Request_& request, const World& world);
ss::GetEntitiesStates_Response_ get_entities_states(const ss::GetEntitiesStates_Request_& request,
                                                    const World& world);
ss::GetEntityState_Response_ get_entity_state(const ss::GetEntityState_Request_& request,
                                              const World& world);
/// Sets an object's pose and twist at once (in header.frame_id: the world, or an entity);
/// nothing changes if any part is refused. Robots move by their wheels only.
ss::SetEntityState_Response_ set_entity_state(const ss::SetEntityState_Request_& request,
                                              World& world);
ss::GetEntityInfo_Response_ get_entity_info(const ss::GetEntityInfo_Request_& request,
                                            const World& world);
/// The axis-aligned box around the entity's shapes, in the entity's frame.
ss::GetEntityBounds_Response_ get_entity_bounds(const ss::GetEntityBounds_Request_& request,
                                                const World& world);
/// Spawns this project's XML: an <ENVIRONMENT> file (uri) or text (resource_string). One
/// object takes the entity's name; several are named <name>/<their ID> and <name> deletes them.
ss::SpawnEntity_Response_ spawn_entity(const ss::SpawnEntity_Request_& request, World& world);
ss::SpawnEntities_Response_ spawn_entities(const ss::SpawnEntities_Request_& request, World& world);
/// Deletes an object (a door part takes its door with it), or every object spawned under a name.
ss::DeleteEntity_Response_ delete_entity(const ss::DeleteEntity_Request_& request, World& world);
/// The environment files beside the world's file and in `sources` (folders).
ss::GetSpawnables_Response_ get_spawnables(const ss::GetSpawnables_Request_& request,
                                           const World& world);
ss::GetCurrentWorld_Response_ get_current_world(const World& world);
/// The world files beside the current world's file and in the additional sources (folders).
ss::GetAvailableWorlds_Response_ get_available_worlds(
    const ss::GetAvailableWorlds_Request_& request, const World& world);
/// Resets what the scope says: state (poses), state and time, or all (spawned objects go).
ss::ResetSimulation_Response_ reset_simulation(const ss::ResetSimulation_Request_& request,
                                               World& world);

/// A service's request as the runner queues it (Req: its request's PubSubType).
template <class Req>
using ServiceRequest = TypedRequest<Req>;

/// The services whose requests can change the world (their requests' PubSubTypes): a session
/// records one that did (the server says when), and a replay runs it again (replay_on(), one
/// entry each).
using WorldChangingServices =
    std::tuple<ss::SetEntityState_Request_PubSubType, ss::SpawnEntity_Request_PubSubType,
               ss::SpawnEntities_Request_PubSubType, ss::DeleteEntity_Request_PubSubType,
               ss::ResetSimulation_Request_PubSubType, ss::SetSimulationState_Request_PubSubType>;

template <class Req, class Services = WorldChangingServices>
inline constexpr bool kChangesWorld = false;
/// True for a service of WorldChangingServices.
template <class Req, class... Services>
inline constexpr bool kChangesWorld<Req, std::tuple<Services...>> =
    (std::is_same_v<Req, Services> || ...);

/// From now on the runner runs the service requests a session recorded as their server did,
/// without answering them (a replay).
void replay_on(Runner& runner);
/// The typed request of a service request a session recorded; nullptr for a service that
/// changes no world, or bytes that are not its request.
std::shared_ptr<const Request> read_recorded(const WireRequest& recorded);

}  // namespace macsim::sim_interfaces
