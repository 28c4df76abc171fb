"""deploy/: `cpack -G DEB` makes the Debian packages an installation is made of, with Debian's
package names as dependencies and the project's version; the service units they hold are
hardened (systemd-analyze security, offline) and start the installed programs; and macsim,
taken from its package, runs the way its unit runs it: as an unprivileged user, with no
capability, publishing to a controller of another user."""

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from conftest import BUILD_DIR, readable_by_all

VERSION_FILE = BUILD_DIR / "CPackConfig.cmake"
PACKAGES = ["macsim-common", "macsim", "kurt-adapter", "macsim-dev", "python3-macsim"]
UNITS = {"macsim": "macsim.service", "macsim-discovery": "macsim-discovery.service",
         "kurt-adapter": "kurt_adapter.service"}


def run(argv, **kwargs):
    result = subprocess.run([str(a) for a in argv], capture_output=True, text=True, **kwargs)
    assert result.returncode == 0, f"{argv}\n{result.stdout}\n{result.stderr}"
    return result.stdout


def project_version():
    return re.search(r'set\(CPACK_PACKAGE_VERSION "([^"]+)"\)', VERSION_FILE.read_text()).group(1)


@pytest.fixture(scope="module")
def debs(tmp_path_factory):
    out = tmp_path_factory.mktemp("debs")
    run(["cpack", "-G", "DEB", "--config", VERSION_FILE, "-B", out], cwd=out)
    found = {}
    for deb in out.glob("*.deb"):
        found[run(["dpkg-deb", "--field", deb, "Package"]).strip()] = deb
    return found


@pytest.fixture(scope="module")
def root(debs):
    """The packages unpacked into a folder, as dpkg would lay them out under /; outside pytest's
    own temporary folder, which other users may not enter."""
    path = readable_by_all(Path(tempfile.mkdtemp(prefix="macsim_packages_")))
    for deb in debs.values():
        run(["dpkg-deb", "-x", deb, path])
    yield path
    shutil.rmtree(path)


def field(deb, name):
    return run(["dpkg-deb", "--field", deb, name]).strip()


def contents(deb):
    return run(["dpkg-deb", "--contents", deb])


def test_one_package_per_part_with_the_projects_version(debs):
    assert sorted(debs) == sorted(PACKAGES)
    for deb in debs.values():
        assert field(deb, "Version") == project_version()
        assert run(["dpkg-deb", "--info", deb])  # a well-formed package


def test_dependencies_are_debian_packages(debs):
    simulator = field(debs["macsim"], "Depends")
    for name in ["libfastrtps2.9", "libode8", "libtinyxml2-9", "libopencv-core406", "fastdds-tools",
                 f"macsim-common (= {project_version()})"]:
        assert name in simulator, simulator
    robot = field(debs["kurt-adapter"], "Depends")
    assert "libfastrtps2.9" in robot and "macsim-common" in robot, robot
    # The robot's computer gets no rendering, physics, image or GUI libraries.
    for name in ["opencv", "libgl", "libegl", "libglut", "libode", "libx11", "python"]:
        assert name not in robot, robot
    dev = field(debs["macsim-dev"], "Depends")
    for name in ["libfastrtps-dev", "libfastcdr-dev", "libopencv-core-dev", "libopencv-ml-dev"]:
        assert name in dev, dev
    assert "libopencv-dev" not in dev, dev  # every module of OpenCV, with VTK, Qt and GDAL
    python = field(debs["python3-macsim"], "Depends")
    assert "python3-numpy" in python and "libfastrtps2.9" in python, python


def test_each_package_holds_its_files(debs):
    expected = {
        "macsim-common": ["./usr/share/macsim/dds/localhost.xml", "./usr/share/macsim/dds/service.xml",
                          "./usr/bin/macsim_shm_clean", "./usr/share/macsim/security/make_security.sh"],
        "macsim": ["./usr/bin/macsim", "./usr/bin/kurt_demo", "./usr/bin/helloKurt",
                   "./usr/bin/macsim_topic", "./usr/bin/macsim_web", "./usr/bin/affordance_trials",
                   "./usr/share/macsim/worlds/DemoWorld_v1.xml", "./usr/share/macsim/web/index.html",
                   "./usr/lib/systemd/system/macsim.service",
                   "./usr/lib/systemd/system/macsim-discovery.service"],
        "kurt-adapter": ["./usr/bin/kurt_adapter", "./usr/bin/kurt_emulator",
                         "./usr/lib/systemd/system/kurt_adapter.service"],
        "macsim-dev": ["./usr/include/macsim/client/robot_client.h",
                       "./usr/include/macsim/msg/nav_msgs.h", "/libmacsim_client.a",
                       "/cmake/macsim/macsimConfig.cmake", "/cmake/macsim/macsimTargets.cmake"],
        "python3-macsim": ["./usr/lib/python3/dist-packages/macsim/__init__.py",
                           "./usr/lib/python3/dist-packages/macsim/_macsim.pyi"],
    }
    listed = {name: contents(deb) for name, deb in debs.items()}
    for name, files in expected.items():
        for file in files:
            assert file in listed[name], f"{name} lacks {file}:\n{listed[name]}"
    # Each file is in one package only; the robot's has no simulator.
    assert "bin/macsim\n" not in listed["kurt-adapter"]
    assert "kurt_adapter\n" not in listed["macsim"]


def exposure(unit_file):
    text = run(["systemd-analyze", "security", "--offline=yes", unit_file], cwd="/")
    return float(re.search(r"Overall exposure level for \S+: ([0-9.]+)", text).group(1))


def test_units_are_hardened_and_start_installed_programs(root):
    for unit in UNITS.values():
        path = root / "usr/lib/systemd/system" / unit
        text = path.read_text()
        score = exposure(path)
        assert score <= 2.5, f"{unit}: exposure {score}"
        exec_start = re.search(r"^ExecStart=(\S+)", text, re.M).group(1)
        assert exec_start.startswith("/usr/bin/"), exec_start
        for setting in ["DynamicUser=yes", "ProtectSystem=strict", "ProtectHome=yes", "PrivateTmp=yes",
                        "NoNewPrivileges=yes", "CapabilityBoundingSet=\n", "RestrictAddressFamilies="]:
            assert setting in text, f"{unit} lacks {setting}"
    # The check is real: a unit without the hardening rates far worse.
    bare = root / "bare.service"
    bare.write_text("[Service]\nExecStart=/usr/bin/macsim\n")
    assert exposure(bare) > 8


def unit_command(unit_text, overrides, root, state="/var/lib"):
    """ExecStart with ${VAR} and $VAR taken from the unit's Environment= (as systemd expands
    them, without /etc/default), %S (the state folders' root) as `state`, installed paths under
    `root`."""
    env = {}
    for m in re.finditer(r'^Environment="?([A-Z_]+)=(.*?)"?$', unit_text, re.M):
        env[m.group(1)] = m.group(2)
    env.update(overrides)
    argv = []
    for word in re.search(r"^ExecStart=(.*)$", unit_text, re.M).group(1).split():
        m = re.fullmatch(r"\$\{([A-Z_]+)\}", word)
        if m:
            argv.append(env[m.group(1)])
        elif re.fullmatch(r"\$([A-Z_]+)", word):
            argv.extend(env[word[1:]].split())  # systemd splits $VAR at white space
        else:
            argv.append(word.replace("%S", str(state)))
    return [str(root) + a if a.startswith("/usr/") else a for a in argv]


def test_macsim_runs_unprivileged_as_its_unit_runs_it(root, domain, spawn):
    assert os.geteuid() == 0, "this test runs programs as nobody and daemon (setpriv): run it as root"
    text = (root / "usr/lib/systemd/system/macsim.service").read_text()
    # The unit's own defaults (its world, its arguments), on the test's domain, on this machine.
    # Its state folder as StateDirectory=macsim makes it: the service's own, mode 0700.
    assert re.search(r"^StateDirectory=macsim$", text, re.M), text
    state = Path(tempfile.mkdtemp(prefix="macsim_state_"))
    state.chmod(0o755)
    (state / "macsim").mkdir(mode=0o700)
    os.chown(state / "macsim", 65534, 65534)  # nobody, as below
    argv = unit_command(text, {"MACSIM_DOMAIN": str(domain),
                               "MACSIM_PROFILE": "/usr/share/macsim/dds/service_localhost.xml"}, root,
                        state)
    assert "--resume" in argv and str(state / "macsim/session.macsim") in argv, argv
    assert argv[0] == f"{root}/usr/bin/macsim", argv
    umask = re.search(r"^UMask=(\d+)$", text, re.M).group(1)
    # The service's user: no root, no capability, none to gain (setpriv, as DynamicUser= and
    # CapabilityBoundingSet= leave the program).
    sim = spawn(["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "--no-new-privs",
                 "--inh-caps=-all", "--bounding-set=-all", "--", "sh", "-c",
                 f'umask {umask}; exec "$@"', "macsim", *argv],
                env={"PATH": "/usr/bin:/bin", "HOME": "/nonexistent"})
    assert sim.wait_for_output("stepping", 60), sim.output()
    status = open(f"/proc/{sim.proc.pid}/status").read()
    assert re.search(r"^Uid:\s+65534\s+65534", status, re.M), status
    assert re.search(r"^CapEff:\s+0+$", status, re.M), status
    # A controller of another user, with the usual profile (shared memory and UDP on 127.0.0.1),
    # sees it publish the robot's odometry. Its programs and profile come from the packages too,
    # so that no folder of the checkout needs to be open to that user.
    reader = ["setpriv", "--reuid=daemon", "--regid=daemon", "--clear-groups", "--no-new-privs",
              root / "usr/bin/macsim_topic", "echo", "/kurt/odom", "--count", "2", "--domain", domain]
    result = subprocess.run([str(a) for a in reader], capture_output=True, text=True, timeout=60,
                            env={"PATH": "/usr/bin:/bin", "FASTRTPS_DEFAULT_PROFILES_FILE":
                                 str(root / "usr/share/macsim/dds/localhost.xml")})
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.count("pose:") >= 2, result.stdout
    assert "macsim" in sim.output() and "DemoWorld_v1" in sim.output()
    # It records its session in its state folder, to resume from when it is started again.
    assert "recording a new one" in sim.output(), sim.output()
    assert (state / "macsim/session.macsim").stat().st_size > 0
    shutil.rmtree(state)
