/* Another vendor's DDS reads macsim's robot and world topics: subscribes with Cyclone DDS (types
 * from the same IDL, by idlc) to ranges, IMU, laser, joint states, crane state, the keyed world
 * state and the door states for `seconds`, writes a crane command, and prints how many samples
 * of each it took. Exit 0 if every topic delivered, 1 otherwise.
 *   cyclone_listen DOMAIN [SECONDS] */
#include <dds/dds.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "kurt_msgs.h"
#include "macsim_msgs.h"
#include "sensor_msgs.h"

struct Subscription {
  const char* topic;
  const dds_topic_descriptor_t* type;
  int reliable_latched; /* 1: reliable + transient local (the world state), 0: best effort */
  dds_entity_t reader;
  int taken;
};

int main(int argc, char** argv) {
  if (argc < 2) {
    printf("usage: cyclone_listen DOMAIN [SECONDS]\n");
    return 2;
  }
  const dds_domainid_t domain = (dds_domainid_t)atoi(argv[1]);
  const int seconds = argc > 2 ? atoi(argv[2]) : 5;
  dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) return 1;
  struct Subscription subs[] = {
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
  dds_entity_t crane_topic = dds_create_topic(participant, &kurt_msgs_msg_dds__CraneCommand__desc,
                                              "rt/kurt/crane/command", NULL, NULL);
  dds_qos_t* reliable = dds_create_qos();
  dds_qset_reliability(reliable, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_entity_t crane_writer = dds_create_writer(participant, crane_topic, reliable, NULL);
  dds_delete_qos(reliable);
  kurt_msgs_msg_dds__CraneCommand_ lift = {0.0, 0.3, 0.0};

  void* samples[8] = {NULL};
  dds_sample_info_t infos[8];
  double slew_seen = -1;
  for (int tick = 0; tick < seconds * 20; ++tick) {
    dds_write(crane_writer, &lift);
    for (int i = 0; i < n; ++i) {
      int got;
      while ((got = dds_take(subs[i].reader, samples, infos, 8, 8)) > 0) {
        for (int k = 0; k < got; ++k) {
          if (!infos[k].valid_data) continue;
          ++subs[i].taken;
          if (i == 4) slew_seen = ((kurt_msgs_msg_dds__CraneState_*)samples[k])->lift;
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
  dds_delete(participant);
  return missing || slew_seen < 0.25 ? 1 : 0;
}
