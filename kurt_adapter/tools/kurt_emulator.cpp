// kurt_emulator: a KURT microcontroller (C167) and rotunit on the userspace CAN bus, for tests
// and for running kurt_adapter without the robot. Every 10 ms it answers like the firmware:
// ENCODER ticks from the commanded speeds through a first-order motor model, ADC frames with
// IR/sonar values for the configured distances, GYRO from the resulting turn, TILT level,
// the rotunit's angle, then BUMPER (the end of a cycle). It logs every change of the commands
// it receives, stamped with the steady clock (CLOCK_MONOTONIC, seconds), so tests can time them.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <map>
#include <thread>

#include "macsim/dds/command_line.h"
#include "macsim/dds/log.h"
#include "macsim/kurt/kurt_can.h"
#include "macsim/robot/kurt3d_description.h"

namespace {

using namespace macsim::kurt;
using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

double now_seconds() {
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions unused;
  std::string can_spec;
  double tau = 0.05, watchdog = 0.5, default_range = 0.5;
  std::vector<std::string> ranges;
  macsim::dds::CommandLine cli(
      "kurt_emulator",
      "Emulates the KURT's microcontroller and rotunit on the userspace CAN bus (a test tool).\n"
      "Logs: 't=SECONDS speed_cm L R', 't=SECONDS HARD STOP', 't=SECONDS actuator on|off',\n"
      "'t=SECONDS rotunit N', 't=SECONDS watchdog: no command for 0.5 s, motors off'.");
  cli.participant_options(&unused);  // --domain is accepted for uniformity: no DDS here
  cli.option("can", "BUS", "the bus, udp:LOCAL_PORT:PEER_PORT (required)", &can_spec);
  cli.option("motor-tau", "SECONDS", "time constant of the wheels' speed (default 0.05)", &tau);
  cli.option("watchdog", "SECONDS", "motors off after this long without CONTROL (default 0.5)",
             &watchdog);
  cli.option("range", "METERS", "distance every IR/sonar sensor sees (default 0.5)",
             &default_range);
  cli.repeated_option("sensor-range", "FRAME=METERS", "distance one sensor sees, e.g. ir_left=0.3",
                      &ranges);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (can_spec.empty() || tau <= 0 || watchdog <= 0) {
    macsim::log::error(
        "kurt_emulator: --can udp:LOCAL:PEER is required; --motor-tau and --watchdog must be "
        "positive");
    return 2;
  }
  std::map<std::string, double> distance;
  for (const auto& c : kRangeChannels) distance[c.frame] = default_range;
  for (const auto& r : ranges) {
    const auto eq = r.find('=');
    if (eq == std::string::npos || !distance.count(r.substr(0, eq))) {
      macsim::log::error(
          "kurt_emulator: --sensor-range takes FRAME=METERS with a KURT sensor frame (e.g. "
          "ir_left), got '{}'",
          r);
      return 2;
    }
    distance[r.substr(0, eq)] = std::atof(r.c_str() + eq + 1);
  }
  std::unique_ptr<CanTransport> can;
  try {
    can = open_can(can_spec);
  } catch (const CanError& e) {
    macsim::log::error("kurt_emulator: {}", e.what());
    return 1;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("kurt_emulator: on %s\n", can_spec.c_str());
  std::fflush(stdout);

  const macsim::KurtDriveParams params;
  constexpr double dt = 0.01;
  double target[2] = {0, 0}, speed[2] = {0, 0}, travel[2] = {0, 0};
  macsim::EncoderCounter encoders[2] = {macsim::EncoderCounter(params.ticks_per_turn),
                                        macsim::EncoderCounter(params.ticks_per_turn)};
  double yaw = 0.0, rotunit_angle = 0.0, rotunit_speed = 0.0;
  double last_control = now_seconds();
  bool motors_off = false;
  int last_cm[2] = {0, 0};
  auto log = [](const std::string& what) {
    std::printf("t=%.6f %s\n", now_seconds(), what.c_str());
    std::fflush(stdout);
  };
  auto next = Clock::now();
  while (!g_stop.load()) {
    next += std::chrono::milliseconds(10);
    // Commands until the cycle is due.
    while (auto frame = can->receive(
               std::max(std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now()),
                        std::chrono::milliseconds(0)))) {
      if (auto c = decode_control(*frame)) {
        last_control = now_seconds();
        motors_off = false;
        if (c->mode == ControlMode::SpeedCm) {
          if (c->left_cm != last_cm[0] || c->right_cm != last_cm[1]) {
            log("speed_cm " + std::to_string(c->left_cm) + " " + std::to_string(c->right_cm));
          }
          last_cm[0] = c->left_cm;
          last_cm[1] = c->right_cm;
          target[0] = c->left_cm / 100.0;
          target[1] = c->right_cm / 100.0;
        } else if (c->hard_stop) {
          log("HARD STOP");
          target[0] = target[1] = speed[0] = speed[1] = 0.0;
          last_cm[0] = last_cm[1] = 0;
        } else if (c->mode == ControlMode::ActuatorOn || c->mode == ControlMode::ActuatorOff) {
          log(std::string("actuator ") + (c->mode == ControlMode::ActuatorOn ? "on" : "off"));
        }
      } else if (auto r = decode_rotunit_speed(*frame)) {
        log("rotunit " + std::to_string(*r));
        rotunit_speed = macsim::rotunit_speed_from_command(*r);
      }
      if (Clock::now() >= next) break;
    }
    if (!motors_off && now_seconds() - last_control > watchdog) {
      log("watchdog: no command for " + std::to_string(watchdog) + " s, motors off");
      motors_off = true;
      target[0] = target[1] = 0.0;
    }
    // One firmware cycle: the wheels follow their set-points, the sensors report.
    const double follow = 1.0 - std::exp(-dt / tau);
    for (int side = 0; side < 2; ++side) {
      speed[side] += (target[side] - speed[side]) * follow;
      travel[side] += speed[side] * dt;
    }
    // The encoders count the wheels' turning: travel / radius is the wheel angle.
    const int16_t left = encoders[0].ticks_since_last(travel[0] / params.wheel_radius());
    const int16_t right = encoders[1].ticks_since_last(travel[1] / params.wheel_radius());
    yaw += (speed[1] - speed[0]) / params.axis_length * params.turning_adaptation * dt;
    yaw = std::remainder(yaw, 2 * M_PI);
    rotunit_angle = std::fmod(rotunit_angle + rotunit_speed * dt + 2 * M_PI, 2 * M_PI);

    std::array<uint16_t, 16> adc{};
    for (const auto& c : kRangeChannels) {
      const double d = distance[c.frame];
      adc[c.channel] = static_cast<uint16_t>(c.sonar ? macsim::sonar_raw_from_range(d)
                                                     : macsim::ir_raw_from_range(d));
    }
    for (int first = 0; first < 16; first += 4) {
      AdcValues v;
      v.first_channel = first;
      for (int i = 0; i < 4; ++i) v.raw[i] = adc[first + i];
      can->send(encode_adc(v));
    }
    can->send(encode_encoder({left, right}));
    can->send(encode_tilt(32768, 32768));
    can->send(encode_gyro(
        static_cast<int32_t>(std::lround(yaw * 180 / M_PI * kGyroCountsPerDegree)), 1000));
    constexpr int kTicks = macsim::robot::kurt3d::kRotunitTicks;
    can->send(encode_rotunit_angle(static_cast<int>(rotunit_angle / (2 * M_PI) * kTicks) % kTicks));
    CanFrame bumper;
    bumper.id = can_id::kBumper;
    can->send(bumper);
    std::this_thread::sleep_until(next);
  }
  std::printf("kurt_emulator: stopped\n");
  return 0;
}
