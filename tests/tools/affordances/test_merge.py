"""affordance_trials merge on files alone (no DDS, no Slurm): shards joined and sorted by seed,
identical duplicates kept once, rows of one trial that differ refused naming both files and
the seed (exit 3), seeds missing reported per shard (exit 1), files of other columns refused
(exit 2); and --shard's blocks, seen through a shard of no trials (which starts no simulator)."""

import os
import subprocess
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("MACSIM_SOURCE_DIR", Path(__file__).resolve().parents[3]))
BIN_DIR = Path(os.environ.get("MACSIM_BIN_DIR", SOURCE_DIR / "build" / "bin"))
PROGRAM = BIN_DIR / "affordance_trials"


def run(*argv):
    return subprocess.run([str(PROGRAM), *map(str, argv)], capture_output=True, text=True,
                          timeout=60, stdin=subprocess.DEVNULL)


@pytest.fixture(scope="module")
def header(tmp_path_factory):
    """The header this version writes: that of a shard with no trials (shard 0 of 2 of one
    trial), which writes its file and exits 0 without starting a simulator."""
    out = tmp_path_factory.mktemp("header") / "empty.csv"
    result = run("--domain", 0, "--trials", 1, "--shard", "0/2", "--out", out)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "shard 0/2: seeds -, 0 to run" in result.stderr, result.stderr
    lines = out.read_text().splitlines()
    assert len(lines) == 1 and lines[0].startswith("affordance,generator,seed,label,")
    return lines[0]


def row(header, seed, label="liftable", wall="0.25", instance="0", affordance="lift"):
    """A row of `header`'s columns: the trial's key, a label, fillers, instance, wall time."""
    fillers = ["0.5"] * (len(header.split(",")) - 6)
    return ",".join([affordance, "material", str(seed), label, *fillers, instance, wall])


def write(path, header, rows):
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


def test_shards_are_joined_sorted_with_identical_duplicates_kept_once(header, tmp_path):
    a = write(tmp_path / "a.csv", header, [row(header, s) for s in (5, 3, 4)])
    # Seed 4 again from another instance and wall time: the same trial, kept once.
    b = write(tmp_path / "b.csv", header, [row(header, s) for s in (10, 1, 2)] +
              [row(header, 4, instance="1", wall="9.5")])
    c = write(tmp_path / "c.csv", header, [row(header, s) for s in (9, 6, 8, 7)])
    out = tmp_path / "out.csv"
    result = run("merge", "--out", out, "--trials", 10, "--shards", 3, a, b, c)
    assert result.returncode == 0, result.stdout + result.stderr
    lines = out.read_text().splitlines()
    assert lines[0] == header
    assert [int(r.split(",")[2]) for r in lines[1:]] == list(range(1, 11))
    assert lines[1:].count(row(header, 4)) == 1 and row(header, 4, "liftable", "9.5", "1") not in lines
    # --shard's blocks of 10 trials in 3: [0,3) [3,6) [6,10).
    for expected in ["shard 0: seeds 1-3, done 3, missing 0", "shard 1: seeds 4-6, done 3, missing 0",
                     "shard 2: seeds 7-10, done 4, missing 0", "1 identical duplicate(s) kept once",
                     "no seed missing"]:
        assert expected in result.stdout, result.stdout


def test_rows_of_one_trial_that_differ_are_refused_naming_both_files_and_the_seed(header, tmp_path):
    a = write(tmp_path / "a.csv", header, [row(header, s) for s in (1, 2, 3)])
    b = write(tmp_path / "b.csv", header, [row(header, 3, label="not_liftable"), row(header, 4)])
    out = tmp_path / "out.csv"
    result = run("merge", "--out", out, "--trials", 4, a, b)
    assert result.returncode == 3, result.stdout + result.stderr
    assert f"lift,material seed 3 differs between {a} and {b}" in result.stderr, result.stderr
    assert not out.exists(), "a refused merge wrote its output"


def test_missing_seeds_are_reported_per_shard_and_the_rows_there_are_written(header, tmp_path):
    shard0 = write(tmp_path / "s0.csv", header, [row(header, s) for s in range(11, 21)])
    shard1 = write(tmp_path / "s1.csv", header, [row(header, s) for s in (21, 22, 24, 26)])
    empty = tmp_path / "s2.csv"
    empty.write_text("")  # a task killed before it wrote its header
    out = tmp_path / "out.csv"
    result = run("merge", "--out", out, "--seed", 11, "--trials", 30, "--shards", 3,
                 shard0, shard1, empty)
    assert result.returncode == 1, result.stdout + result.stderr
    for expected in ["shard 0: seeds 11-20, done 10, missing 0",
                     "shard 1: seeds 21-30, done 4, missing 6 (23 25 27 28 29 30)",
                     "shard 2: seeds 31-40, done 0, missing 10 (31 32 33 34 35 36 37 38 ...)",
                     "16 seed(s) missing"]:
        assert expected in result.stdout, result.stdout
    assert len(out.read_text().splitlines()) == 1 + 14
    # Without --trials: the gaps between the smallest and the largest seed found.
    result = run("merge", "--out", out, shard1)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "found: seeds 21-26, done 4, missing 2 (23 25)" in result.stdout, result.stdout


def test_files_of_other_columns_and_bad_usage_are_refused_with_exit_2(header, tmp_path):
    good = write(tmp_path / "good.csv", header, [row(header, 1)])
    other = write(tmp_path / "other.csv", header.replace(",label,", ",verdict,"), [row(header, 2)])
    short = write(tmp_path / "short.csv", header, [row(header, 2).rsplit(",", 5)[0], row(header, 3)])
    out = tmp_path / "out.csv"
    for argv, says in [
            ([good, other], f"{other} has other columns than this version writes"),
            ([good, short], f"{short}:2: "),
            ([good, tmp_path / "none.csv"], "no such file"),
            ([], "name the files to merge"),
            (["--shards", 2, good], "--shards needs --trials"),
            (["--trials", 2, "--shards", 3, good], "more than --trials"),
            (["--affordance", "fly", good], "unknown --affordance 'fly'"),
            (["--seed", "-1", good], "--seed takes a whole number"),
            (["--bogus", good], "unknown option '--bogus'")]:
        result = run("merge", "--out", out, *argv)
        assert result.returncode == 2, (argv, result.stdout, result.stderr)
        assert says in result.stderr, (argv, result.stderr)
        assert not out.exists(), argv
    result = run("merge", good)
    assert result.returncode == 2 and "--out OUT.csv" in result.stderr, result.stderr
    result = run("merge", "--help")
    assert result.returncode == 0 and "usage: affordance_trials merge" in result.stdout


def test_a_bad_shard_is_refused_before_anything_starts(tmp_path):
    for shard in ["4/4", "1", "-1/4", "a/b", "1/0", "0/4x"]:
        result = run("--domain", 0, "--trials", 4, "--shard", shard, "--out", tmp_path / "x.csv")
        assert result.returncode == 2, (shard, result.stderr)
        assert "--shard takes I/N" in result.stderr, (shard, result.stderr)
        assert not (tmp_path / "x.csv").exists()
