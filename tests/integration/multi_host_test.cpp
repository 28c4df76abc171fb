// Two hosts: macsim and helloKurt in two network namespaces joined by a veth pair, so every DDS
// packet crosses a real network link (shared memory cannot help: Fast DDS sees two hosts).
// Once with SIMPLE discovery (multicast over the link, deploy/dds/network.xml), once through a
// Fast DDS discovery server (deploy/run_discovery_server.sh, ROS_DISCOVERY_SERVER), with the
// negative control that without the server nothing is found. Needs CAP_SYS_ADMIN/CAP_NET_ADMIN
// (root); elsewhere the tests skip and say why.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

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
