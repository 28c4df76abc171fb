"""The operations generator (idl/tools/generate_operations.py) on the project's IDL and on
copies of it broken on purpose: the IDL as shipped generates; each broken copy is refused with
exit 1 and an error that names the file and the line where it is broken."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("MACSIM_SOURCE_DIR", Path(__file__).resolve().parents[2]))
SCRIPT = SOURCE_DIR / "idl" / "tools" / "generate_operations.py"
IDL = SOURCE_DIR / "idl" / "kurt" / "macsim_msgs.idl"


def generate(idl, tmp_path):
    return subprocess.run([sys.executable, str(SCRIPT), str(idl), "--out-doc",
                           str(tmp_path / "operations.md")], capture_output=True, text=True,
                          timeout=60)


def line_of(lines, start):
    """The 0-based index of the first line that starts (after blanks) with `start`."""
    return next(i for i, line in enumerate(lines) if line.strip().startswith(start))


def test_the_shipped_idl_generates(tmp_path):
    result = generate(IDL, tmp_path)
    assert result.returncode == 0, result.stderr
    assert "set_density" in (tmp_path / "operations.md").read_text()


def break_field(lines):
    i = line_of(lines, "struct ObjectName_") + 1
    lines[i] = "  string name the object's full name;"
    return i


def break_comment(lines):
    i = line_of(lines, "const int32 OP_FIND_OBJECT")
    lines[i] = lines[i].replace("ObjectName_:", "NoSuchStruct_:")
    return i


def break_annotation(lines):
    i = line_of(lines, "const int32 OP_LIST_OBJECTS")
    lines[i] = lines[i].replace("//@ python=manual", "//@ python=manual stray")
    return i


def break_reply(lines):
    i = line_of(lines, "const int32 OP_FIND_OBJECT")
    lines[i] = lines[i].replace("-> object_id, index", "-> object_id, no_such_field")
    return i


def break_union(lines):
    i = line_of(lines, "const int32 OP_GET_OBJECT")
    lines[i] = lines[i].replace("ObjectRef_:", "ObjectName_:")
    return i


@pytest.mark.parametrize("breaker", [break_field, break_comment, break_annotation, break_reply,
                                     break_union])
def test_each_error_names_the_file_and_the_line(tmp_path, breaker):
    lines = IDL.read_text().splitlines()
    i = breaker(lines)
    broken = tmp_path / "broken.idl"
    broken.write_text("\n".join(lines) + "\n")
    result = generate(broken, tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    assert f"{broken}:{i + 1}: " in result.stderr, (i + 1, result.stderr)
    assert "Traceback" not in result.stderr, result.stderr
