"""deploy/slurm/ on a real one-node Slurm cluster (conftest.py): a job array of 4 tasks x 10 lift
trials and its dependent merge give the rows of one affordance_trials run of the same 40 seeds;
a task cancelled mid-run leaves its shard short, the merge names the missing seeds, and the
task run again (the command the submit script prints) fills exactly those rows; stopping the
cluster while tasks run leaves no process behind."""

import os
import re
import shlex
import signal
import subprocess
import time

import pytest

from conftest import BIN_DIR, SLURM_DIR, descendants, marked

TRIALS, SHARDS = 40, 4
FINAL = ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY")


def result_part(row):
    """A row without its last two columns (instance, wall time): what must be the same."""
    return row.rsplit(",", 2)[0]


def rows(path):
    lines = path.read_text().splitlines()
    return lines[0], lines[1:]


def seed_of(row):
    return int(row.split(",")[2])


@pytest.fixture(scope="module")
def reference(tmp_path_factory, domains):
    """The 40 seeds in one process, one simulator (affordance_trials --instances 1)."""
    out = tmp_path_factory.mktemp("reference") / "lift.csv"
    result = subprocess.run(
        [BIN_DIR / "affordance_trials", "--domain", str(domains + SHARDS), "--instances", "1",
         "--trials", str(TRIALS), "--out", out, "--logs", out.parent / "logs"],
        capture_output=True, text=True, timeout=240)
    assert result.returncode == 0, result.stdout + result.stderr
    header, body = rows(out)
    assert [seed_of(r) for r in body] == list(range(1, TRIALS + 1))
    return header, [result_part(r) for r in body]


def submit(cluster, out_dir, domains, *more):
    """submit_affordances.sh: the array and the merge; their ids and the re-run commands."""
    result = cluster.run([SLURM_DIR / "submit_affordances.sh", "--out-dir", out_dir,
                          "--trials", TRIALS, "--shards", SHARDS, "--instances", 1,
                          "--bin", BIN_DIR, "--domain-base", domains, "--domain-blocks", SHARDS,
                          "--lock-dir", out_dir / "locks", *more])
    said = result.stdout
    array_job = re.search(r"array job (\d+)", said).group(1)
    merge_job = re.search(r"merge job (\d+)", said).group(1)
    rerun = re.search(r"^  (sbatch --array=I .*)$", said, re.M).group(1)
    merge = re.search(r"^  then merge: (sbatch .*)$", said, re.M).group(1)
    return array_job, merge_job, shlex.split(rerun), shlex.split(merge), said


def simulator_logs(out_dir, shard):
    """The ends of the logs a task's simulators left (kept by the trials when one was lost)."""
    folder = out_dir / "logs" / f"lift-shard-{shard}-of-{SHARDS}"
    tails = []
    for log in sorted(folder.rglob("*")) if folder.is_dir() else []:
        if log.is_file():
            tails.append(f"\n--- {log.name} (end) ---\n{log.read_text(errors='replace')[-3000:]}")
    return "".join(tails)


def wait_array(cluster, array_job, count, timeout=150):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        cluster.reap()
        tasks = cluster.array_tasks(array_job)
        if len(tasks) == count and all(t["JobState"] in FINAL for t in tasks.values()):
            return tasks
        time.sleep(0.2)
    raise AssertionError(f"array {array_job} not done after {timeout} s: "
                         f"{ {i: t['JobState'] for i, t in cluster.array_tasks(array_job).items()} }\n"
                         f"{cluster.log_tails()}")


def sbatch(cluster, argv):
    """Submits a job (argv: an sbatch command) and waits for its end (polling scontrol, faster
    than sbatch --wait); its id and scontrol's fields (of its one task for an array)."""
    job = cluster.run(argv[:1] + ["--parsable"] + argv[1:]).stdout.strip().split(";")[0]
    if any(a.startswith("--array=") for a in argv):
        return job, next(iter(wait_array(cluster, job, 1).values()))
    return job, cluster.wait_job(job)


def test_an_array_of_four_tasks_and_its_merge_give_the_rows_of_one_run(cluster, domains, reference,
                                                                       tmp_path):
    out_dir = tmp_path / "a"
    started = time.monotonic()
    array_job, merge_job, _, _, said = submit(cluster, out_dir, domains)
    tasks = wait_array(cluster, array_job, SHARDS)
    outputs = {i: (out_dir / f"slurm-{array_job}_{i}.out").read_text() for i in range(SHARDS)}
    for i, task in tasks.items():
        assert task["JobState"] == "COMPLETED" and task["ExitCode"] == "0:0", \
            outputs[i] + simulator_logs(out_dir, i)
    merge = cluster.wait_job(merge_job)
    report = (out_dir / f"slurm-merge-{merge_job}.out").read_text()
    assert merge["JobState"] == "COMPLETED" and merge["ExitCode"] == "0:0", report
    print(f"array of {SHARDS} x {TRIALS // SHARDS} and merge: {time.monotonic() - started:.1f} s")

    # The merged file is the one-process run's, but for instance and wall time.
    header, merged = rows(out_dir / "lift.csv")
    assert header == reference[0]
    assert [result_part(r) for r in merged] == reference[1]
    # Each task ran its block of seeds on a domain of its own, and said so in its output.
    domains_used = set()
    for i in range(SHARDS):
        first, last = i * 10 + 1, i * 10 + 10
        _, shard = rows(out_dir / f"lift-shard-{i}-of-{SHARDS}.csv")
        assert [seed_of(r) for r in shard] == list(range(first, last + 1)), outputs[i]
        assert f"shard {i}/{SHARDS}: seeds {first}-{last}, 10 to run" in outputs[i], outputs[i]
        assert f"shard {i}/{SHARDS}: trials 10/10," in outputs[i], outputs[i]
        used = re.search(r"on domains (\d+)\.\.(\d+)", outputs[i])
        assert used and used.group(1) == used.group(2), outputs[i]
        domains_used.add(int(used.group(1)))
        assert f"shard {i}: seeds {first}-{last}, done 10, missing 0" in report, report
    assert domains_used <= set(range(domains, domains + SHARDS)), domains_used
    assert "no seed missing" in report, report
    assert "submit_affordances: array job" in said


def test_a_task_cancelled_mid_run_and_run_again_fills_exactly_its_missing_rows(
        cluster, domains, reference, tmp_path):
    out_dir = tmp_path / "b"
    killed = SHARDS - 1
    array_job, merge_job, rerun, merge, _ = submit(cluster, out_dir, domains)
    shard_file = out_dir / f"lift-shard-{killed}-of-{SHARDS}.csv"
    # Cancel the task once it has written a row (a whole line), well before its tenth: its
    # affordance_trials is stopped (SIGSTOP) at once, so that Slurm's cancel (SIGCONT, SIGTERM,
    # SIGKILL after KillWait) cannot come too late however fast the trials run.
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        text = shard_file.read_text() if shard_file.exists() else ""
        if text.count("\n") >= 2 and text.endswith("\n"):
            task = [pid for pid, c in cluster.processes().items()
                    if "bin/affordance_trials " in c and f"--shard {killed}/{SHARDS} " in c]
            assert len(task) == 1, cluster.processes()
            os.kill(task[0], signal.SIGSTOP)
            break
        time.sleep(0.01)
    else:
        pytest.fail(f"task {killed} wrote no row in 120 s\n{cluster.log_tails()}")
    cluster.run(["scancel", f"{array_job}_{killed}"])
    tasks = wait_array(cluster, array_job, SHARDS)
    assert tasks[killed]["JobState"] == "CANCELLED", tasks[killed]
    for i in range(killed):
        assert tasks[i]["JobState"] == "COMPLETED", tasks[i]
    _, before = rows(shard_file)
    assert 1 <= len(before) < 10, f"the cancel came too late: {len(before)} rows"
    # The dependent merge never runs: a task of its array did not succeed.
    assert cluster.wait_job(merge_job)["Reason"] == "DependencyNeverSatisfied"
    cluster.run(["scancel", merge_job])

    # The merge before the re-run names the shard's missing seeds (exit 1).
    first_seed = killed * 10 + 1
    missing = sorted(set(range(first_seed, first_seed + 10)) - {seed_of(r) for r in before})
    job, fields = sbatch(cluster, merge)
    report = (out_dir / f"slurm-merge-{job}.out").read_text()
    assert fields["ExitCode"] == "1:0", (fields, report)
    for i in range(killed):
        assert f"shard {i}: seeds {i * 10 + 1}-{i * 10 + 10}, done 10, missing 0" in report, report
    listed = " ".join(map(str, missing[:8])) + (" ..." if len(missing) > 8 else "")
    expected = (f"shard {killed}: seeds {first_seed}-{first_seed + 9}, done {len(before)}, "
                f"missing {len(missing)} ({listed})")
    assert expected in report, report

    # The task run again, as the submit script said: only the missing rows are run.
    again = [a.replace("--array=I", f"--array={killed}") for a in rerun]
    job, fields = sbatch(cluster, again)
    output = (out_dir / f"slurm-{job}_{killed}.out").read_text()
    assert fields["JobState"] == "COMPLETED" and fields["ExitCode"] == "0:0", (fields, output)
    assert f"{len(before)} trials already in" in output, output
    assert f"{len(missing)} trials run" in output, output
    _, after = rows(shard_file)
    assert set(before) <= set(after), "a row written before the cancel was run again"
    assert [seed_of(r) for r in after] == list(range(first_seed, first_seed + 10))

    job, fields = sbatch(cluster, merge)
    report = (out_dir / f"slurm-merge-{job}.out").read_text()
    assert fields["JobState"] == "COMPLETED" and fields["ExitCode"] == "0:0", (fields, report)
    header, merged = rows(out_dir / "lift.csv")
    assert header == reference[0]
    assert [result_part(r) for r in merged] == reference[1]


def test_stopping_the_cluster_while_tasks_run_leaves_no_process_behind(cluster, domains, tmp_path):
    """Runs last: it stops the module's cluster."""
    out_dir = tmp_path / "c"
    result = cluster.run([SLURM_DIR / "submit_affordances.sh", "--out-dir", out_dir,
                          "--trials", 2000, "--shards", 2, "--bin", BIN_DIR,
                          "--domain-base", domains, "--domain-blocks", 2,
                          "--lock-dir", out_dir / "locks"])
    array_job = re.search(r"array job (\d+)", result.stdout).group(1)
    files = [out_dir / f"lift-shard-{i}-of-2.csv" for i in range(2)]
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline:
        if all(f.exists() and f.read_text().count("\n") >= 2 for f in files):
            break
        time.sleep(0.1)
    else:
        pytest.fail(f"the tasks of {array_job} did not both write a row\n{cluster.log_tails()}")
    # While they run: both tasks' programs and simulators, under the cluster's step daemons,
    # are seen, both as descendants of the test and by the cluster's marker.
    running = cluster.processes()
    commands = list(running.values())
    for name, count in [("slurmstepd", 2), ("bin/affordance_trials", 2), ("bin/macsim ", 2),
                        ("munged", 1), ("slurmctld", 1), ("slurmd", 1)]:
        assert sum(name in c for c in commands) >= count, (name, running)
    assert set(marked(cluster.marker)) & set(descendants()), running

    left = cluster.stop()
    assert left == {}, f"left behind (killed): {left}"
    for pid in running:
        try:
            state = open(f"/proc/{pid}/status").read()
        except OSError:
            continue
        pytest.fail(f"process {pid} ({running[pid]}) still there:\n{state[:200]}")
    assert descendants() == {}
    assert marked(cluster.marker) == {}
