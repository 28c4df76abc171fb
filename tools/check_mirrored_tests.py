#!/usr/bin/env python3
"""Every production source has a test of its name, or says in tests/README.md why not.

The rule (tests/README.md, "Where is the test for X"): the unit test of `<folder>/.../NAME.cpp`
is `tests/<folder>/NAME_test.cpp`, where <folder> is the source's top folder, `render` for
`sim_core/render/` and `tools/<tool>` for a tool. A source without one must have a row in that
section's table headed `| source |` saying where it is tested instead. Fails (exit 1) naming
each source with neither; a row naming a source that is gone or has its test now is reported
(to be removed) but does not fail: renaming a file or adding its test never breaks the check.

    check_mirrored_tests.py [SOURCE_DIR]      (default: the repository this script is in)

Sources are the C and C++ files git tracks under the production folders (new files count once
added to git); outside a git checkout, every such file there.
"""
import os
import re
import subprocess
import sys
from pathlib import Path

PRODUCTION_FOLDERS = ("idl", "sim_core", "dds_bridge", "kurt_adapter", "affordances", "examples",
                      "tools")
SECTION = "## Where is the test for X"


def test_folder(source: str) -> str:
    parts = source.split("/")
    if parts[0] == "sim_core" and len(parts) > 2 and parts[1] == "render":
        return "tests/render"
    if parts[0] == "tools" and len(parts) > 2:
        return "tests/tools/" + parts[1]
    return "tests/" + parts[0]


def mirrored_test(source: str) -> str:
    return f"{test_folder(source)}/{Path(source).stem}_test.cpp"


def sources(root: Path) -> list:
    try:
        listed = subprocess.run(["git", "-C", str(root), "ls-files", "--", *PRODUCTION_FOLDERS],
                                capture_output=True, text=True, check=True).stdout.split("\n")
    except (OSError, subprocess.CalledProcessError):
        listed = []
        for folder in PRODUCTION_FOLDERS:
            for dirpath, dirnames, filenames in os.walk(root / folder):
                dirnames[:] = [d for d in dirnames if not d.startswith(".") and d != "node_modules"]
                listed += [str(Path(dirpath, f).relative_to(root)) for f in filenames]
    return sorted(s for s in listed
                  if s.endswith((".cpp", ".c")) and (root / s).is_file())


def exempted(readme: Path) -> dict:
    """The rows of the section's table headed `| source |`: source path -> line number."""
    rows, section, table = {}, False, False
    for number, line in enumerate(readme.read_text().splitlines(), 1):
        if line.startswith("## "):
            section = line.strip() == SECTION
        table = section and (line.startswith("| source |") or (table and line.startswith("|")))
        m = re.match(r"\|\s*`([^`]+\.(?:cpp|c))`\s*\|", line) if table else None
        if m:
            rows[m.group(1)] = number
    return rows


def main() -> int:
    root = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent)
    readme = root / "tests/README.md"
    rows = exempted(readme)
    problems, stale, mirrored = [], [], 0
    all_sources = sources(root)
    for source in all_sources:
        has_test = (root / mirrored_test(source)).is_file()
        mirrored += has_test
        if not has_test and source not in rows:
            problems.append(f"{source}: no test {mirrored_test(source)} and no row in "
                            f"tests/README.md (\"{SECTION[3:]}\") saying where it is tested")
        if has_test and source in rows:
            stale.append(f"tests/README.md:{rows[source]}: {source} has its test "
                            f"{mirrored_test(source)} now: remove its row")
    for source, line in rows.items():
        if source not in all_sources:
            stale.append(f"tests/README.md:{line}: {source} is not a production source "
                            "(moved or removed?): update or remove its row")
    for p in stale + problems:
        print(p)
    print(f"{len(all_sources)} production sources: {mirrored} with a test of their name, "
          f"{len(all_sources) - mirrored} without"
          + (f"; {len(stale)} rows to remove" if stale else "")
          + (f"; {len(problems)} sources with neither" if problems else ""))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
