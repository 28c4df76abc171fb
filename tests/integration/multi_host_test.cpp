// Two hosts: macsim and helloKurt in two network namespaces joined by a veth pair, so every DDS
// packet crosses a real network link (shared memory cannot help: Fast DDS sees two hosts).
// Once with SIMPLE discovery (multicast over the link, deploy/dds/network.xml), once through a
// Fast DDS discovery server (deploy/run_discovery_server.sh, ROS_DISCOVERY_SERVER), with the
// negative control that without the server nothing is found. Needs CAP_SYS_ADMIN/CAP_NET_ADMIN
// (root); elsewhere the tests skip and say why. Packet loss on the link comes from nftables'
// random drop (netem, the usual tool, is missing from some kernels: delay is not tested here).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "macsim/client/robot_client.h"
#include "macsim/client/supervisor_client.h"
#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

std::string ip_tool() {
  for (const char* p : {"/usr/bin/ip", "/bin/ip", "/usr/sbin/ip", "/sbin/ip"}) {
    if (access(p, X_OK) == 0) return p;
  }
  return "";
}

/// Runs a shell command quietly; true on exit status 0.
bool run(const std::string& command) {
  return std::system((command + " >/dev/null 2>&1").c_str()) == 0;
}

class TwoHosts : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = unique_test_domain();
    ip_ = ip_tool();
    if (ip_.empty()) GTEST_SKIP() << "no `ip` tool (iproute2): cannot build two hosts";
    const std::string d = std::to_string(domain_);
    host_a_ = "macsim_a" + d;
    host_b_ = "macsim_b" + d;
    address_a_ = "10.231." + d + ".1";
    address_b_ = "10.231." + d + ".2";
    run(ip_ + " netns del " + host_a_);
    run(ip_ + " netns del " + host_b_);
    if (!run(ip_ + " netns add " + host_a_)) {
      GTEST_SKIP() << "cannot create network namespaces here (needs root or CAP_SYS_ADMIN)";
    }
    created_ = true;
    const std::string va = "mva" + d, vb = "mvb" + d;
    const bool ok = run(ip_ + " netns add " + host_b_) &&
                    run(ip_ + " link add " + va + " type veth peer name " + vb) &&
                    run(ip_ + " link set " + va + " netns " + host_a_) &&
                    run(ip_ + " link set " + vb + " netns " + host_b_) &&
                    run(ip_ + " -n " + host_a_ + " addr add " + address_a_ + "/24 dev " + va) &&
                    run(ip_ + " -n " + host_b_ + " addr add " + address_b_ + "/24 dev " + vb) &&
                    run(ip_ + " -n " + host_a_ + " link set lo up") &&
                    run(ip_ + " -n " + host_b_ + " link set lo up") &&
                    run(ip_ + " -n " + host_a_ + " link set " + va + " up multicast on") &&
                    run(ip_ + " -n " + host_b_ + " link set " + vb + " up multicast on");
    ASSERT_TRUE(ok) << "could not wire the two namespaces";
  }
  void TearDown() override {
    if (!created_) return;
    run(ip_ + " netns del " + host_a_);  // deletes the veth pair with it
    run(ip_ + " netns del " + host_b_);
  }

  /// argv running `program` on host `ns`.
  std::vector<std::string> on(const std::string& ns, std::vector<std::string> argv) const {
    argv.insert(argv.begin(), {ip_, "netns", "exec", ns});
    return argv;
  }
  std::vector<std::string> macsim() const {
    return on(host_a_, {bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                        std::to_string(domain_), "--cameras", "off"});
  }
  std::vector<std::string> hello_kurt(const std::string& discovery_timeout) const {
    return on(host_b_, {bin("helloKurt"), "--domain", std::to_string(domain_), "--distance", "0.3",
                        "--discovery-timeout", discovery_timeout});
  }
  /// Bytes host b's end of the link has received.
  long received_on_b() const {
    FILE* p = popen((ip_ + " netns exec " + host_b_ + " cat /sys/class/net/mvb" +
                     std::to_string(domain_) + "/statistics/rx_bytes")
                        .c_str(),
                    "r");
    long bytes = -1;
    if (p) {
      if (std::fscanf(p, "%ld", &bytes) != 1) bytes = -1;
      pclose(p);
    }
    return bytes;
  }

  /// Drops `percent` % of the UDP packets host `ns` receives over the link, at random
  /// (nftables; 0 removes the rule). False if nft is missing or refused.
  bool lose(const std::string& ns, int percent) const {
    const std::string nft = ip_ + " netns exec " + ns + " nft ";
    run(nft + "delete table inet macsim_loss");
    if (percent == 0) return true;
    return run(nft + "add table inet macsim_loss") &&
           run(nft + "'add chain inet macsim_loss in { type filter hook input priority 0; }'") &&
           run(nft +
               "add rule inet macsim_loss in iifname != lo meta l4proto udp numgen random "
               "mod 100 '<' " +
               std::to_string(percent) + " drop");
  }

  /// What a controller on host b sees in `seconds`: odometry samples (best effort) and the
  /// sim time they span (so that a simulator slowed by a loaded machine, which publishes fewer
  /// per wall second, is not taken for loss), and how many of `calls` supervisor calls
  /// (reliable request and reply) were answered.
  struct Seen {
    long odometry = -1;
    double sim_seconds = 0;
    int answered = -1;
    double per_sim_second() const { return sim_seconds > 0 ? (odometry - 1) / sim_seconds : 0; }
  };
  Seen probe_from_b(int seconds, int calls) const {
    int out[2];
    if (pipe(out) != 0) return {};
    const pid_t child = fork();
    if (child == 0) {  // in host b's network, a participant of its own
      close(out[0]);
      const int ns = open(("/var/run/netns/" + host_b_).c_str(), O_RDONLY);
      if (ns < 0 || setns(ns, CLONE_NEWNET) != 0) _exit(3);
      Seen seen;
      {
        dds::Participant participant({domain_, "", "loss_probe"});
        std::mutex mutex;
        bool counting = false;
        long odometry = 0, arrived = 0;
        double first = 0, last = 0;
        dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType> odom(
            participant, dds::topics::odom("kurt"), dds::QosFamily::Sensor,
            [&](const nav_msgs::msg::dds_::Odometry_& o) {
              const double t = o.header().stamp().sec() + o.header().stamp().nanosec() * 1e-9;
              std::lock_guard<std::mutex> lock(mutex);
              ++arrived;
              if (!counting) return;
              if (odometry++ == 0) first = t;
              last = std::max(last, t);
            });
        client::SupervisorClient supervisor(participant);
        if (!supervisor.wait_for_server(std::chrono::seconds(30))) _exit(4);
        // Discovery over a lossy link takes a while, and the reader may know the writer well
        // before the writer knows the reader (each learns of the other by its own, lossy,
        // announcement): count from the first sample that came.
        auto arrivals = [&] {
          std::lock_guard<std::mutex> lock(mutex);
          return arrived;
        };
        for (int i = 0; i < 600 && arrivals() == 0; ++i) {
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        {
          std::lock_guard<std::mutex> lock(mutex);
          counting = true;
        }
        std::this_thread::sleep_for(std::chrono::seconds(seconds));
        {
          std::lock_guard<std::mutex> lock(mutex);
          counting = false;
          seen.odometry = odometry;
          seen.sim_seconds = last - first;
        }
        seen.answered = 0;
        for (int i = 0; i < calls; ++i) {
          // Lossy and slow is not lost: each call may take as long as the busiest run needs.
          auto reply = supervisor.call(client::supervisor::state_hash(), std::chrono::seconds(30));
          if (reply && reply->code() == macsim_msgs::msg::dds_::ERR_OK) ++seen.answered;
        }
      }
      const bool written = write(out[1], &seen, sizeof seen) == sizeof seen;
      _exit(written ? 0 : 5);
    }
    close(out[1]);
    Seen seen;
    if (read(out[0], &seen, sizeof seen) != sizeof seen) seen = {};
    close(out[0]);
    int status = 0;
    waitpid(child, &status, 0);
    return seen;
  }

  int domain_ = 0;
  std::string ip_, host_a_, host_b_, address_a_, address_b_;
  bool created_ = false;
};

TEST_F(TwoHosts, AControllerOnAnotherHostDrivesTheRobot) {
  ScopedEnv profile("FASTRTPS_DEFAULT_PROFILES_FILE", source("deploy/dds/network.xml"));
  ChildProcess sim(macsim());
  ASSERT_TRUE(sim.wait_for_output("stepping", 30s)) << sim.output();
  const long before = received_on_b();
  ChildProcess controller(hello_kurt("20"));
  EXPECT_EQ(controller.wait_for_exit(60s), 0) << controller.output() << sim.output();
  EXPECT_NE(controller.output().find("arrived"), std::string::npos) << controller.output();
  // The odometry came over the link: host b received far more than discovery alone sends.
  EXPECT_GT(received_on_b() - before, 100000) << "bytes received on host b's link";
}

TEST_F(TwoHosts, AffordanceTrialsRunOnASimulatorOnAnotherHost) {
  // Lock-step trials over a real link: the simulator on host a, the trial runner on host b.
  ScopedEnv profile("FASTRTPS_DEFAULT_PROFILES_FILE", source("deploy/dds/network.xml"));
  ChildProcess sim(on(host_a_, {bin("macsim"), "--world", source("worlds/affordance_trials.xml"),
                                "--domain", std::to_string(domain_), "--lockstep",
                                "--camera-rate", "1.25"}));
  ASSERT_TRUE(sim.wait_for_output("stepping", 30s)) << sim.output();
  TempDir dir("affordance_hosts_");
  const long before = received_on_b();
  ChildProcess trials(on(host_b_, {bin("affordance_trials"), "--attach", std::to_string(domain_),
                                   "--trials", "3", "--seed", "4", "--out",
                                   dir.path() + "/rows.csv"}));
  ASSERT_EQ(trials.wait_for_exit(120s), 0) << trials.output() << sim.output();
  std::ifstream rows(dir.path() + "/rows.csv");
  int lines = 0;
  for (std::string line; std::getline(rows, line);) ++lines;
  EXPECT_EQ(lines, 4) << trials.output();  // the header and three rows
  EXPECT_GT(received_on_b() - before, 100000) << "bytes received on host b's link";
}

TEST_F(TwoHosts, UnderPacketLossReliableTopicsLoseNothingAndSensorsDegradeByTheLossRate) {
  ScopedEnv profile("FASTRTPS_DEFAULT_PROFILES_FILE", source("deploy/dds/network.xml"));
  ChildProcess sim(macsim());
  ASSERT_TRUE(sim.wait_for_output("stepping", 30s)) << sim.output();
  const Seen clean = probe_from_b(6, 20);
  ASSERT_GT(clean.odometry, 100) << "no odometry over the clean link";
  ASSERT_EQ(clean.answered, 20);
  for (int percent : {10, 30}) {
    SCOPED_TRACE(std::to_string(percent) + " % loss");
    ASSERT_TRUE(lose(host_a_, percent) && lose(host_b_, percent)) << "nft refused the rules";
    const Seen lossy = probe_from_b(6, 20);
    lose(host_a_, 0);
    lose(host_b_, 0);
    EXPECT_EQ(lossy.answered, 20) << "a reliable request or reply was lost";
    const double kept = lossy.per_sim_second() / clean.per_sim_second();
    std::printf(
        "loss %d %%: odometry kept %.3f of the clean link's (%.1f against %.1f samples "
        "per sim second), %d of 20 supervisor calls answered\n",
        percent, kept, lossy.per_sim_second(), clean.per_sim_second(), lossy.answered);
    // Best effort: about the loss rate (a datagram may carry more than one sample), no more.
    EXPECT_GT(kept, 1.0 - percent / 100.0 - 0.15);
    EXPECT_LT(kept, 1.0 - percent / 100.0 + 0.08);
  }
  EXPECT_TRUE(sim.running()) << sim.output();
}

TEST_F(TwoHosts, ThroughADiscoveryServerAndNotWithoutIt) {
  ScopedEnv profile("FASTRTPS_DEFAULT_PROFILES_FILE", source("deploy/dds/network.xml"));
  ScopedEnv server_address("ROS_DISCOVERY_SERVER", address_a_ + ":11811");
  {
    // Negative control: clients only talk to the server, and there is none yet.
    ChildProcess sim(macsim());
    ASSERT_TRUE(sim.wait_for_output("stepping", 30s)) << sim.output();
    ChildProcess controller(hello_kurt("4"));
    EXPECT_EQ(controller.wait_for_exit(30s), 2) << controller.output();
    EXPECT_NE(controller.output().find("no odometry"), std::string::npos) << controller.output();
  }
  ChildProcess server(on(host_a_, {source("deploy/run_discovery_server.sh"), address_a_}));
  ASSERT_TRUE(server.wait_for_output("Server is running", 20s)) << server.output();
  ChildProcess sim(macsim());
  ASSERT_TRUE(sim.wait_for_output("stepping", 30s)) << sim.output();
  ChildProcess controller(hello_kurt("20"));
  EXPECT_EQ(controller.wait_for_exit(60s), 0) << controller.output() << sim.output();
  EXPECT_NE(controller.output().find("arrived"), std::string::npos) << controller.output();
}

}  // namespace
}  // namespace macsim::test
