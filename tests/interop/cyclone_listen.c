/* Another vendor's DDS reads macsim's robot and world topics: subscribes with Cyclone DDS (types
 * from the same IDL, by idlc) to the clock, odometry, ground truth, ranges, IMU, laser, point
 * clouds, joint states, crane state, the stereo images and camera infos, the keyed world state
 * and the door states for `seconds`; writes a crane command; calls the supervisor (find an
 * object by name, then get it by the id found), turns the rotunit (for clouds), switches the
 * magnet on (seen in the crane state), drives by wheel speeds for 2 s (seen in odometry),
 * triggers the door's switch through the supervisor and hears the world event and the simulation
 * control (features) through their request/reply topics; prints how many samples of each it took
 * and the replies. Exit 0 if every topic delivered and every call was answered, 1 otherwise.
 *   cyclone_listen DOMAIN [SECONDS] [OBJECT_NAME] */
#include <dds/dds.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry_msgs.h"
#include "kurt_msgs.h"
#include "macsim_msgs.h"
#include "nav_msgs.h"
#include "rosgraph_msgs.h"
#include "sensor_msgs.h"

struct Subscription {
  const char* topic;
  const dds_topic_descriptor_t* type;
  int reliable_latched; /* 1: reliable + transient local (the world state), 0: best effort */
  dds_entity_t reader;
  int taken;
};

/* A reliable, volatile writer or reader (keep last 10) on a new topic: the QoS of macsim's
 * commands, requests, replies and events. */
static dds_qos_t* reliable_qos(void) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
  return qos;
}
static dds_entity_t reliable_writer(dds_entity_t participant, const dds_topic_descriptor_t* type,
                                    const char* name) {
  dds_qos_t* qos = reliable_qos();
  const dds_entity_t writer = dds_create_writer(
      participant, dds_create_topic(participant, type, name, NULL, NULL), qos, NULL);
  dds_delete_qos(qos);
  return writer;
}
static dds_entity_t reliable_reader(dds_entity_t participant, const dds_topic_descriptor_t* type,
                                    const char* name) {
  dds_qos_t* qos = reliable_qos();
  const dds_entity_t reader = dds_create_reader(
      participant, dds_create_topic(participant, type, name, NULL, NULL), qos, NULL);
  dds_delete_qos(qos);
  return reader;
}

int main(int argc, char** argv) {
  const char* usage =
      "usage: cyclone_listen DOMAIN [SECONDS] [OBJECT_NAME]  (DOMAIN 1..232; it drives the robot, "
      "moves the crane and triggers a door there)";
  if (argc > 1 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
    printf("%s\n", usage);
    return 0;
  }
  /* It commands a robot: never on a bad argument or the default domain 0. */
  char* end = NULL;
  const long domain_number = argc > 1 ? strtol(argv[1], &end, 10) : 0;
  if (argc < 2 || *end != '\0' || domain_number < 1 || domain_number > 232) {
    fprintf(stderr, "%s\n", usage);
    return 2;
  }
  const dds_domainid_t domain = (dds_domainid_t)domain_number;
  const int seconds = argc > 2 ? atoi(argv[2]) : 5;
  const char* object_name = argc > 3 ? argv[3] : "environment_01/ball_green";
  dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) return 1;
  struct Subscription subs[] = {
      {"rt/clock", &rosgraph_msgs_msg_dds__Clock__desc, 0, 0, 0},
      {"rt/kurt/odom", &nav_msgs_msg_dds__Odometry__desc, 0, 0, 0},
      {"rt/kurt/ground_truth", &nav_msgs_msg_dds__Odometry__desc, 0, 0, 0},
      {"rt/kurt/points", &sensor_msgs_msg_dds__PointCloud2__desc, 0, 0, 0},
      {"rt/kurt/camera/left/image_raw", &sensor_msgs_msg_dds__Image__desc, 0, 0, 0},
      {"rt/kurt/camera/right/image_raw", &sensor_msgs_msg_dds__Image__desc, 0, 0, 0},
      {"rt/kurt/camera/left/camera_info", &sensor_msgs_msg_dds__CameraInfo__desc, 0, 0, 0},
      {"rt/kurt/range", &sensor_msgs_msg_dds__Range__desc, 0, 0, 0},
      {"rt/kurt/imu", &sensor_msgs_msg_dds__Imu__desc, 0, 0, 0},
      {"rt/kurt/scan360", &sensor_msgs_msg_dds__LaserScan__desc, 0, 0, 0},
      {"rt/kurt/joint_states", &sensor_msgs_msg_dds__JointState__desc, 0, 0, 0},
      {"rt/kurt/crane/state", &kurt_msgs_msg_dds__CraneState__desc, 0, 0, 0},
      {"rt/macsim/world/objects", &macsim_msgs_msg_dds__ObjectState__desc, 1, 0, 0},
      {"rt/macsim/world/doors", &macsim_msgs_msg_dds__DoorState__desc, 1, 0, 0},
  };
  const int n = (int)(sizeof subs / sizeof subs[0]);
  for (int i = 0; i < n; ++i) {
    dds_entity_t topic = dds_create_topic(participant, subs[i].type, subs[i].topic, NULL, NULL);
    dds_qos_t* qos = dds_create_qos();
    if (subs[i].reliable_latched) {
      dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
      dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    } else {
      dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
    }
    subs[i].reader = dds_create_reader(participant, topic, qos, NULL);
    dds_delete_qos(qos);
  }
  dds_entity_t crane_writer =
      reliable_writer(participant, &kurt_msgs_msg_dds__CraneCommand__desc, "rt/kurt/crane/command");
  kurt_msgs_msg_dds__CraneCommand_ lift = {0.0, 0.3, 0.0};
  /* The rotunit turns the laser (no 3D clouds while it stands): 2 rad/s over rt/kurt/rot_vel. */
  dds_entity_t rot_writer =
      reliable_writer(participant, &geometry_msgs_msg_dds__Twist__desc, "rt/kurt/rot_vel");
  /* The magnet (crane state reports it) and the wheels (odometry shows them) for 2 s. */
  dds_entity_t magnet_writer =
      reliable_writer(participant, &kurt_msgs_msg_dds__MagnetCommand__desc, "rt/kurt/crane/magnet");
  dds_entity_t wheels_writer =
      reliable_writer(participant, &kurt_msgs_msg_dds__WheelSpeeds__desc, "rt/kurt/wheel_speeds");
  kurt_msgs_msg_dds__MagnetCommand_ magnet_on = {true};
  kurt_msgs_msg_dds__WheelSpeeds_ wheels = {0.15, 0.15};
  int magnet_seen = 0;
  double fastest = 0.0;
  geometry_msgs_msg_dds__Twist_ turn;
  memset(&turn, 0, sizeof turn);
  turn.angular.z = 2.0;

  /* The supervisor and the simulation control: request/reply pairs correlated in the payload
   * (client id + sequence number), reliable and volatile. A request is repeated every tick
   * until its reply comes (macsim answers a repeat without doing it again). */
  dds_entity_t sup_request = reliable_writer(
      participant, &macsim_msgs_msg_dds__SupervisorRequest__desc, "rt/macsim/supervisor/request");
  dds_entity_t sup_reply = reliable_reader(participant, &macsim_msgs_msg_dds__SupervisorReply__desc,
                                           "rt/macsim/supervisor/reply");
  dds_entity_t sim_request = reliable_writer(
      participant, &macsim_msgs_msg_dds__SimulationRequest__desc, "rt/macsim/simulation/request");
  dds_entity_t sim_reply = reliable_reader(participant, &macsim_msgs_msg_dds__SimulationReply__desc,
                                           "rt/macsim/simulation/reply");
  /* World events (reliable, volatile): the switch triggered through the supervisor below. */
  dds_entity_t events = reliable_reader(participant, &macsim_msgs_msg_dds__WorldEvent__desc,
                                        "rt/macsim/world/events");
  macsim_msgs_msg_dds__SupervisorRequest_ request;
  memset(&request, 0, sizeof request);
  char empty[] = "";
  request.client_id = (char*)"cyclone_listen";
  request.sequence_number = 1;
  /* The operation is a union: its discriminator is the OP_* code, its member the arguments. */
  request.operation._d = macsim_msgs_msg_dds__OP_FIND_OBJECT;
  request.operation._u.find_object.name = (char*)object_name;
  macsim_msgs_msg_dds__SimulationRequest_ sim = {
      (char*)"cyclone_listen", 1, macsim_msgs_msg_dds__SIM_FEATURES, 0, 0.0, empty};
  uint32_t found_id = 0;
  int got_object = 0, got_features = 0, switched = 0, event_seen = 0;

  void* samples[8] = {NULL};
  dds_sample_info_t infos[8];
  double slew_seen = -1;
  for (int tick = 0; tick < seconds * 20; ++tick) {
    dds_write(crane_writer, &lift);
    dds_write(rot_writer, &turn);
    dds_write(magnet_writer, &magnet_on);
    if (tick < 40) dds_write(wheels_writer, &wheels);
    if (!switched) dds_write(sup_request, &request);
    if (!got_features) dds_write(sim_request, &sim);
    int got;
    while ((got = dds_take(sup_reply, samples, infos, 8, 8)) > 0) {
      for (int k = 0; k < got; ++k) {
        const macsim_msgs_msg_dds__SupervisorReply_* r = samples[k];
        if (!infos[k].valid_data || strcmp(r->client_id, request.client_id) != 0 ||
            r->sequence_number != request.sequence_number ||
            r->code == macsim_msgs_msg_dds__ERR_IN_PROGRESS) {  /* progress, not the reply */
          continue;
        }
        if (request.operation._d == macsim_msgs_msg_dds__OP_FIND_OBJECT) {
          printf("cyclone_listen: supervisor FIND_OBJECT %s: code %d, id %u\n", object_name,
                 r->code, r->object_id);
          if (r->code != macsim_msgs_msg_dds__ERR_OK) return 1;
          found_id = r->object_id;
          request.operation._d = macsim_msgs_msg_dds__OP_GET_OBJECT;
          request.operation._u.object.object_id = found_id;
          request.sequence_number = 2;
        } else if (request.operation._d == macsim_msgs_msg_dds__OP_GET_OBJECT) {
          printf("cyclone_listen: supervisor GET_OBJECT %u: code %d, name %s, mass %.3f kg\n",
                 found_id, r->code, r->object.name, r->object.mass);
          got_object =
              r->code == macsim_msgs_msg_dds__ERR_OK && strcmp(r->object.name, object_name) == 0;
          if (!got_object) return 1;
          request.operation._d = macsim_msgs_msg_dds__OP_SET_SWITCH_TRIGGERED;
          request.operation._u.set_switch_triggered.door = 0;
          request.operation._u.set_switch_triggered.triggered = true;
          request.sequence_number = 3;
        } else {
          printf("cyclone_listen: supervisor SET_SWITCH_TRIGGERED 0: code %d\n", r->code);
          switched = r->code == macsim_msgs_msg_dds__ERR_OK ? 1 : -1;
        }
      }
      dds_return_loan(sup_reply, samples, got);
    }
    while ((got = dds_take(events, samples, infos, 8, 8)) > 0) {
      for (int k = 0; k < got; ++k) {
        const macsim_msgs_msg_dds__WorldEvent_* e = samples[k];
        if (!infos[k].valid_data) continue;
        printf("cyclone_listen: event %s %s\n", e->type, e->subject);
        if (strcmp(e->type, "switch_triggered") == 0) event_seen = 1;
      }
      dds_return_loan(events, samples, got);
    }
    while ((got = dds_take(sim_reply, samples, infos, 8, 8)) > 0) {
      for (int k = 0; k < got; ++k) {
        const macsim_msgs_msg_dds__SimulationReply_* r = samples[k];
        if (!infos[k].valid_data || strcmp(r->client_id, sim.client_id) != 0 ||
            r->code == macsim_msgs_msg_dds__ERR_IN_PROGRESS) {
          continue;
        }
        printf("cyclone_listen: simulation FEATURES: code %d, features \"%s\"\n", r->code,
               r->features);
        got_features = r->code == macsim_msgs_msg_dds__ERR_OK && strstr(r->features, "supervisor");
      }
      dds_return_loan(sim_reply, samples, got);
    }
    for (int i = 0; i < n; ++i) {
      while ((got = dds_take(subs[i].reader, samples, infos, 8, 8)) > 0) {
        for (int k = 0; k < got; ++k) {
          if (!infos[k].valid_data) continue;
          ++subs[i].taken;
          if (subs[i].type == &kurt_msgs_msg_dds__CraneState__desc) {
            const kurt_msgs_msg_dds__CraneState_* crane = samples[k];
            slew_seen = crane->lift;
            if (crane->magnet_on) magnet_seen = 1;
          }
          if (strcmp(subs[i].topic, "rt/kurt/odom") == 0) {
            const double v = ((nav_msgs_msg_dds__Odometry_*)samples[k])->twist.twist.linear.x;
            if (v > fastest) fastest = v;
          }
        }
        dds_return_loan(subs[i].reader, samples, got);
      }
    }
    dds_sleepfor(DDS_MSECS(50));
  }
  int missing = 0;
  for (int i = 0; i < n; ++i) {
    printf("cyclone_listen: %-26s %d samples\n", subs[i].topic, subs[i].taken);
    if (subs[i].taken == 0) missing = 1;
  }
  printf("cyclone_listen: crane lift after the command %.3f rad\n", slew_seen);
  printf("cyclone_listen: magnet %s; fastest odometry on wheel_speeds 0.15 m/s: %.3f m/s\n",
         magnet_seen ? "on" : "never on", fastest);
  dds_delete(participant);
  return missing || slew_seen < 0.25 || !got_object || !got_features || !magnet_seen ||
                 fastest < 0.1 || switched != 1 || !event_seen
             ? 1
             : 0;
}
