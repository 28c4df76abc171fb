"""deploy/: `cmake --install` into a prefix of the test's own makes a working installation. A
controller built outside the tree against the installed CMake package drives the installed
macsim; `import macsim` works from the installed files alone; the installed programs find
their data (worlds, profiles, the web page) under the prefix, with no source tree."""

import json
import os
import re
import shutil
import subprocess
import time
import urllib.request

import pytest

from conftest import BUILD_DIR, SOURCE_DIR


def run(argv, **kwargs):
    result = subprocess.run([str(a) for a in argv], capture_output=True, text=True, **kwargs)
    assert result.returncode == 0, f"{argv}\n{result.stdout}\n{result.stderr}"
    return result.stdout


@pytest.fixture(scope="module")
def prefix(tmp_path_factory):
    path = tmp_path_factory.mktemp("prefix")
    run(["cmake", "--install", BUILD_DIR, "--prefix", path])
    return path


@pytest.fixture
def installed_env(prefix, tmp_path):
    """What a user of the installation has: its programs, its profile, its Python path; no
    variable that names the source or build tree."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith("MACSIM_") and k not in ("PYTHONPATH", "FASTRTPS_DEFAULT_PROFILES_FILE")}
    env["PATH"] = f"{prefix}/bin:/usr/bin:/bin"
    env["FASTRTPS_DEFAULT_PROFILES_FILE"] = str(prefix / "share/macsim/dds/localhost.xml")
    env["PYTHONPATH"] = str(prefix / "lib/python3/dist-packages")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def test_the_prefix_holds_programs_data_sdk_units_and_python(prefix):
    for name in ["macsim", "kurt_demo", "helloKurt", "kurt_adapter", "kurt_emulator",
                 "macsim_topic", "macsim_web", "affordance_trials", "macsim_shm_clean"]:
        assert os.access(prefix / "bin" / name, os.X_OK), name
    for relative in ["share/macsim/worlds/DemoWorld_v1.xml", "share/macsim/worlds/affordance_trials.xml",
                     "share/macsim/dds/localhost.xml", "share/macsim/dds/service.xml",
                     "share/macsim/slurm/submit_affordances.sh", "share/macsim/slurm/affordance_array.sbatch",
                     "share/macsim/web/index.html", "share/macsim/web/vendor/three.module.js",
                     "include/macsim/client/robot_client.h", "include/macsim/dds/participant.h",
                     "include/macsim/msg/nav_msgs.h",
                     "lib/systemd/system/macsim.service", "lib/systemd/system/kurt_adapter.service",
                     "lib/python3/dist-packages/macsim/__init__.py"]:
        assert (prefix / relative).is_file(), relative
    # The SDK's libraries and CMake package, in lib/ or lib/<multiarch>/ (GNUInstallDirs).
    for pattern in ["lib*/**/libmacsim_client.a", "lib*/**/cmake/macsim/macsimConfig.cmake",
                    "lib*/**/cmake/macsim/macsimConfigVersion.cmake"]:
        assert list(prefix.glob(pattern)), pattern
    # Nothing of the tests, benchmarks or sanitizers is installed.
    installed = " ".join(str(p.relative_to(prefix)) for p in prefix.rglob("*"))
    for word in ["_tests", "bench_", "asan", "fuzz"]:
        assert word not in installed, word
    # The units start the programs where they are installed, and systemd takes them as they are
    # (verify fails on a unit whose program is missing, or on a setting it cannot parse).
    unit = (prefix / "lib/systemd/system/macsim.service").read_text()
    assert f"ExecStart={prefix}/bin/macsim " in unit, unit
    for name in ["macsim", "kurt_adapter", "macsim-discovery"]:
        result = subprocess.run(["systemd-analyze", "verify", prefix / f"lib/systemd/system/{name}.service"],
                                capture_output=True, text=True, cwd="/")
        # Only what it says of this unit (it may warn of units of the host a unit refers to).
        said = [line for line in result.stderr.splitlines() if f"{name}.service" in line]
        assert result.returncode == 0 and not said, f"{name}: {result.stderr}"


def test_a_controller_built_out_of_tree_drives_the_installed_simulator(prefix, installed_env,
                                                                       tmp_path, domain, spawn):
    # The README's snippet, as a project outside the repository, against the installed package.
    project = tmp_path / "my_controller"
    shutil.copytree(SOURCE_DIR / "examples" / "out_of_tree", project)
    build = tmp_path / "build"
    run(["cmake", "-S", project, "-B", build, f"-DCMAKE_PREFIX_PATH={prefix}",
         "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON", "-DCMAKE_BUILD_TYPE=Release"], env=installed_env)
    run(["cmake", "--build", build], env=installed_env)
    # It was compiled against the installed headers, not the tree's.
    commands = json.loads((build / "compile_commands.json").read_text())
    assert str(prefix / "include") in commands[0]["command"]
    assert str(SOURCE_DIR) not in commands[0]["command"]
    assert str(BUILD_DIR) not in commands[0]["command"]

    # The installed macsim, on an installed world named alone (found under the prefix).
    sim = spawn([prefix / "bin" / "macsim", "--world", "small_room.xml", "--domain", domain,
                 "--cameras", "off"], env=installed_env)
    assert sim.wait_for_output("stepping", 60), sim.output()
    assert f"{prefix}/share/macsim/worlds/small_room.xml" in sim.output(), sim.output()
    result = subprocess.run([build / "my_controller", "--domain", str(domain), "--distance", "0.5"],
                            capture_output=True, text=True, env=installed_env, cwd=tmp_path,
                            timeout=90)
    assert result.returncode == 0, result.stdout + result.stderr
    travelled = float(re.search(r"travelled ([0-9.]+) m", result.stdout).group(1))
    assert travelled >= 0.5

    # The installed Python package sees the robot where the controller left it.
    script = ("import macsim, sys\n"
              "assert macsim.__file__.startswith(sys.argv[1]), macsim.__file__\n"
              "robot = macsim.Robot(macsim.Participant(domain=int(sys.argv[2])))\n"
              "print(robot.odometry(timeout=20).position[0])\n")
    result = subprocess.run(["/usr/bin/python3", "-c", script, str(prefix), str(domain)],
                            capture_output=True, text=True, env=installed_env, cwd=tmp_path,
                            timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    assert float(result.stdout.strip()) >= 0.45


def test_an_out_of_tree_controller_loads_a_model_the_installed_learner_saved(prefix, installed_env,
                                                                            tmp_path):
    # macsim::affordances from the installed package, on a model the installed
    # affordance_learn wrote; the installed Python package reads the same file alike.
    models = tmp_path / "models"
    run([prefix / "bin" / "affordance_learn", "--in",
         SOURCE_DIR / "tests" / "tools" / "affordances" / "lift_trials.csv", "--save-model", models],
        env=installed_env)
    project = tmp_path / "ranker"
    project.mkdir()
    (project / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.22)\nproject(ranker LANGUAGES CXX)\n"
        "set(CMAKE_CXX_STANDARD 20)\nfind_package(macsim 0.1 CONFIG REQUIRED)\n"
        "add_executable(ranker ranker.cpp)\n"
        "target_link_libraries(ranker PRIVATE macsim::affordances)\n")
    (project / "ranker.cpp").write_text(
        "#include <cstdio>\n#include \"macsim/affordances/model.h\"\n"
        "int main(int, char** argv) {\n"
        "  const auto model = macsim::affordances::AffordanceModel::load(argv[1]);\n"
        "  std::vector<double> features(model.info().features.size(), 0.1);\n"
        "  const auto p = model.predict(features);\n"
        "  std::printf(\"%s %s %.2f\\n\", model.info().affordance.c_str(), p.label.c_str(),\n"
        "              p.confidence);\n}\n")
    build = tmp_path / "ranker_build"
    # OpenCV's modules as the package finds them without OpenCV's own CMake package (a machine
    # with Debian's module packages and no libopencv-dev), wherever that package is installed.
    configure = run(["cmake", "-S", project, "-B", build, f"-DCMAKE_PREFIX_PATH={prefix}",
                     "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON"],
                    env=installed_env)
    assert "OpenCV: the modules core imgproc ml from" in configure, configure
    run(["cmake", "--build", build], env=installed_env)
    result = subprocess.run([build / "ranker", models / "lift.yml"], capture_output=True,
                            text=True, env=installed_env, timeout=30)
    assert result.returncode == 0, result.stdout + result.stderr
    affordance, label, confidence = result.stdout.split()
    assert affordance == "lift" and label in ("liftable", "not_liftable")
    script = ("import macsim, sys\n"
              "assert macsim.__file__.startswith(sys.argv[1]), macsim.__file__\n"
              "m = macsim.affordances.load(sys.argv[2])\n"
              "label, confidence = m.predict([0.1] * len(m.features))\n"
              "print(label, f'{confidence:.2f}')\n")
    python = subprocess.run(["/usr/bin/python3", "-c", script, str(prefix), str(models / "lift.yml")],
                            capture_output=True, text=True, env=installed_env, timeout=30)
    assert python.returncode == 0, python.stdout + python.stderr
    assert python.stdout.split() == [label, confidence]


def test_installed_programs_find_their_data_under_the_prefix(prefix, installed_env, tmp_path,
                                                             domain, spawn):
    # macsim_web serves the installed page.
    web = spawn([prefix / "bin" / "macsim_web", "--domain", domain, "--port", "0"], env=installed_env)
    assert web.wait_for_output("serving http://", 30), web.output()
    port = re.search(r"serving http://127\.0\.0\.1:(\d+)/", web.output()).group(1)
    page = urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=10).read().decode()
    assert "<canvas" in page or "app.js" in page, page[:500]
    three = urllib.request.urlopen(f"http://127.0.0.1:{port}/vendor/three.module.js", timeout=10)
    assert three.status == 200
    # affordance_trials starts its simulators on the installed trial world by default.
    out = tmp_path / "lift.csv"
    result = subprocess.run([prefix / "bin" / "affordance_trials", "--domain", str(domain),
                             "--trials", "1", "--out", out], capture_output=True, text=True,
                            env=installed_env, cwd=tmp_path, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    assert len(out.read_text().splitlines()) == 2
