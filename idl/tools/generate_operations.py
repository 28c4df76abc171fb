#!/usr/bin/env python3
"""Generates what repeats per supervisor operation from the IDL (kurt/macsim_msgs.idl): the
union SupervisorOperation_, the OP_* constants with their comments (`ArgStruct_: what ->
reply fields: what`), the argument structs and the `//@` annotations in their comments (the
syntax is described at the top of the IDL file).

Each --out-* option names one file to write; only those asked for are written, and a file is
rewritten only when its text changes (so nothing that includes it recompiles needlessly).

  --client-header F   macsim/client/supervisor_requests.h: one typed builder per operation
  --client-source F   its definitions
  --dispatch F        the cases of the supervisor dispatch (included by supervisor_dispatch.cpp)
  --python F          the .def(...) of each Python Supervisor method (included by supervisor.cpp)
  --pyi-template T --pyi F
                      the type stubs: T with its `# @SUPERVISOR_OPERATIONS@` line replaced by
                      the generated Supervisor methods
  --doc F             a markdown table of the operations
"""

import argparse
import re
import sys
from pathlib import Path

MM = "macsim_msgs::msg::dds_::"
GM = "geometry_msgs::msg::dds_::"


class IdlError(Exception):
    pass


def parse_annotations(text):
    """`key=value key=value` -> dict; a value may be double-quoted to hold spaces."""
    out = {}
    for match in re.finditer(r'([\w.]+)=("([^"]*)"|\S+)', text):
        out[match.group(1)] = match.group(3) if match.group(3) is not None else match.group(2)
    rest = re.sub(r'([\w.]+)=("([^"]*)"|\S+)', "", text).strip()
    if rest:
        raise IdlError(f"annotation without key=value: '{rest}'")
    return out


def split_comment(line):
    """A line -> (code, comment text, annotations)."""
    code, _, comment = line.partition("//")
    comment = "//" + comment if comment or line.find("//") >= 0 else ""
    text, annotations = comment, {}
    if "//@" in comment:
        text, _, ann = comment.partition("//@")
        annotations = parse_annotations(ann)
    text = text[2:].strip() if text.startswith("//") else text.strip()
    return code.strip(), text, annotations


class Field:
    def __init__(self, idl_type, name, array, comment, annotations, where):
        self.where = where      # "FILE:LINE" of its declaration, for errors
        self.idl_type = idl_type.split("::")[-1]
        self.name = name
        self.array = array
        self.comment = comment
        self.annotations = annotations


class Param:
    """One parameter of an operation's builder (a Pose_ field gives two)."""

    def __init__(self, field, name, kind, sub=None):
        self.field = field      # the argument struct's field
        self.name = name        # the parameter's name in C++ and Python
        self.kind = kind        # uint32, int32, double, float, boolean, string, vec3, quat, rgba, object
        self.sub = sub          # position / orientation of a Pose_ field
        self.cpp_default = None
        self.py_default = None
        self.comment = field.comment if sub is None else ""


class Operation:
    def __init__(self, const, code, comment, annotations, where):
        self.where = where      # "FILE:LINE" of its OP_ constant, for errors
        self.const = const
        self.code = code
        self.name = const[len("OP_"):].lower()
        self.annotations = annotations
        self.arg_type = None
        self.description = ""
        self.replies = []
        self.reply_description = ""
        self.member = None
        self.params = []
        head, arrow, tail = comment.partition("->")
        arg, _, description = head.partition(":")
        self.arg_type = arg.strip()
        self.description = description.strip()
        if arrow:
            fields, _, self.reply_description = tail.partition(":")
            self.reply_description = self.reply_description.strip()
            for item in fields.split(","):
                word = re.match(r"\s*(\w+)", item)
                if word:
                    self.replies.append(word.group(1))
        if not self.arg_type:
            raise IdlError(f"{where}: {const}: its comment does not name its argument struct "
                           "(or none)")

    @property
    def manual_python(self):
        return self.annotations.get("python") == "manual"

    def cpp_params(self):
        """Parameters in C++ order: those without a default first, in the struct's order."""
        return [p for p in self.params if p.cpp_default is None] + \
               [p for p in self.params if p.cpp_default is not None]

    def py_params(self):
        return [p for p in self.params if p.py_default is None] + \
               [p for p in self.params if p.py_default is not None]




def at_line(path, i, error):
    """An error met reading line i (0-based) of `path`, named FILE:LINE."""
    return IdlError(f"{path}:{i + 1}: {error}")


def parse_idl(path):
    """The operations and structs of the IDL file at `path`; every error names FILE:LINE."""
    lines = Path(path).read_text().splitlines()
    operations = []
    structs = {}
    reply_fields = []
    union = {}
    i = 0
    while i < len(lines):
        line = lines[i]
        m = re.match(r"\s*const\s+int32\s+(OP_\w+)\s*=\s*(\d+)\s*;(.*)$", line)
        if m:
            try:
                _, comment, annotations = split_comment(line)
            except IdlError as e:
                raise at_line(path, i, e)
            operations.append(Operation(m.group(1), int(m.group(2)), comment, annotations,
                                        f"{path}:{i + 1}"))
            i += 1
            continue
        m = re.match(r"\s*struct\s+(\w+)\s*\{", line)
        if m:
            name, fields = m.group(1), []
            i += 1
            while i < len(lines) and not re.match(r"\s*\};", lines[i]):
                try:
                    code, comment, annotations = split_comment(lines[i])
                except IdlError as e:
                    raise at_line(path, i, e)
                f = re.match(r"(?:@\w+\s+)?([\w:]+(?:<[\w:, ]+>)?)\s+(\w+)(?:\[(\d+)\])?\s*;", code)
                if f:
                    fields.append(Field(f.group(1), f.group(2),
                                        int(f.group(3)) if f.group(3) else None, comment,
                                        annotations, f"{path}:{i + 1}"))
                elif code:
                    raise at_line(path, i, f"cannot read the field '{code}'")
                i += 1
            if i == len(lines):
                raise at_line(path, i - 1, f"struct {name} is not closed by '}};'")
            structs[name] = fields
            if name == "SupervisorReply_":
                reply_fields = [f.name for f in fields]
            i += 1
            continue
        m = re.match(r"\s*union\s+SupervisorOperation_\s+switch", line)
        if m:
            i += 1
            labels = []
            while i < len(lines) and not re.match(r"\s*\};", lines[i]):
                try:
                    code, _, _ = split_comment(lines[i])
                except IdlError as e:
                    raise at_line(path, i, e)
                c = re.match(r"case\s+(OP_\w+)\s*:", code)
                f = re.match(r"([\w:]+)\s+(\w+)\s*;", code)
                if c:
                    labels.append(c.group(1))
                elif f:
                    for label in labels:
                        union[label] = (f.group(1).split("::")[-1], f.group(2), i)
                    labels = []
                elif code:
                    raise at_line(path, i, f"cannot read the union line '{code}'")
                i += 1
            if i == len(lines):
                raise at_line(path, i - 1, "union SupervisorOperation_ is not closed by '};'")
        i += 1
    if not operations or not union:
        raise at_line(path, max(len(lines) - 1, 0),
                      "no OP_* constants or no union SupervisorOperation_ in the file")
    for op in operations:
        if op.const not in union:
            raise IdlError(f"{op.where}: {op.const} is not a case of SupervisorOperation_")
        member_type, op.member, member_line = union[op.const]
        if op.arg_type == "none":
            if member_type != "boolean":
                raise at_line(path, member_line,
                              f"{op.const}: 'none' but its member is a {member_type}")
            continue
        if op.arg_type != member_type:
            raise IdlError(f"{op.where}: {op.const}: its comment says {op.arg_type}, the union "
                           f"{member_type} ({path}:{member_line + 1})")
        if op.arg_type not in structs:
            raise IdlError(f"{op.where}: {op.const}: no struct {op.arg_type}")
        for reply in op.replies:
            if reply not in reply_fields:
                raise IdlError(f"{op.where}: {op.const}: '{reply}' is no field of "
                               "SupervisorReply_")
        op.params = make_params(op, structs[op.arg_type])
    return operations, structs


KINDS = {"uint32": "uint32", "int32": "int32", "double": "double", "float": "float",
         "boolean": "boolean", "string": "string", "Point_": "vec3", "Vector3_": "vec3",
         "Quaternion_": "quat", "Object_": "object"}


def make_params(op, fields):
    params = []
    for field in fields:
        if field.idl_type == "Pose_":
            subs = [Param(field, "position", "vec3", "position"),
                    Param(field, "orientation", "quat", "orientation")]
        elif field.array == 4 and field.idl_type == "float":
            subs = [Param(field, field.name, "rgba")]
        elif field.array is None and field.idl_type in KINDS:
            subs = [Param(field, field.name, KINDS[field.idl_type])]
        else:
            raise IdlError(f"{field.where}: {op.const}: no builder parameter for "
                           f"{field.idl_type} {field.name}")
        for p in subs:
            # Field annotations, then the operation's own (prefixed with the field's name).
            for source, prefix in ((field.annotations, ""), (op.annotations, field.name + ".")):
                keys = prefix + (p.sub + "." if p.sub else "")
                if f"{keys}name" in source:
                    p.name = source[f"{keys}name"]
                for lang in ("cpp", "py"):
                    for key in (f"{keys}default", f"{keys}{lang}_default"):
                        if key in source:
                            value = None if source[key] == "-" else source[key]
                            setattr(p, f"{lang}_default", value)
            params.append(p)
    return params


# --- Values of defaults in each language --------------------------------------------------

# How each output spells an identity quaternion, a zero vector and the prefix of an IDL
# constant (None: the stubs write "..." for a constant's value).
SPELLINGS = {
    "cpp": ("kIdentity", "Vec3{0, 0, 0}", MM),
    "pybind": ("sv::kIdentity", "sv::Vec3{0, 0, 0}", "mm::"),
    "pyi": ("(0, 0, 0, 1)", "(0, 0, 0)", None),
}


def default_value(value, kind, output):
    """A default as `output` (cpp, pybind or pyi) writes it."""
    identity, zero_vector, constants = SPELLINGS[output]
    if value == "identity":
        return identity
    if value == "zero":
        return zero_vector if kind == "vec3" else "0"
    if output == "pyi" and value in ("true", "false"):
        return value.capitalize()
    if re.fullmatch(r"[A-Z][A-Z0-9_]+", value):
        return "..." if constants is None else f"{constants}{value}"
    return value


CPP_TYPES = {"uint32": "uint32_t", "int32": "int32_t", "double": "double", "float": "float",
             "boolean": "bool", "string": "const std::string&", "vec3": "const Vec3&",
             "quat": "const Quat&", "rgba": "const Rgba&", "object": f"const {MM}Object_&"}
PYI_TYPES = {"uint32": "int", "int32": "int", "double": "float", "float": "float",
             "boolean": "bool", "string": "str", "vec3": "Sequence[float]",
             "quat": "Sequence[float]", "rgba": "Sequence[float]", "object": "Object"}
REPLY_PYI = {"object_id": "int", "index": "int", "count": "int", "hash": "int",
             "object_ids": "list[int]", "names": "list[str]", "object": "Object", "door": "Door"}


def sentence(text):
    text = text.strip()
    if not text:
        return ""
    text = text[0].upper() + text[1:]
    return text if text.endswith(".") else text + "."


def op_doc(op, python=False):
    """The operation's documentation from the IDL comments: what it does, its arguments' units
    and meanings, what the reply carries (in Python: what the method returns)."""
    parts = []
    if op.description:
        parts.append(sentence(op.description))
    for p in op.params:
        if p.comment:
            parts.append(f"`{p.name}`: {p.comment.rstrip('.')}.")
    if op.replies:
        reply = ("Returns the reply's " + op.replies[0]) if python else \
                ("Reply: " + ", ".join(op.replies))
        if op.reply_description and (not python or len(op.replies) == 1):
            reply += " (" + op.reply_description + ")"
        parts.append(reply + ".")
    return " ".join(parts)


def wrap(text, width, prefix):
    lines, line = [], ""
    for word in text.split():
        if line and len(prefix) + len(line) + 1 + len(word) > width:
            lines.append(prefix + line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    if line:
        lines.append(prefix + line)
    return lines


HEADER_NOTE = "Generated from idl/kurt/macsim_msgs.idl by idl/tools/generate_operations.py; do not edit."


# --- The client's builders -----------------------------------------------------------------

def signature(op, with_defaults):
    out = []
    for p in op.cpp_params():
        text = f"{CPP_TYPES[p.kind]} {p.name}"
        if with_defaults and p.cpp_default is not None:
            text += f" = {default_value(p.cpp_default, p.kind, 'cpp')}"
        out.append(text)
    return ", ".join(out)


def client_header(operations):
    out = [f"// {HEADER_NOTE}",
           "// Typed supervisor requests (macsim_msgs OP_*), one function per operation: each fills its",
           "// operation's own arguments. Send them with SupervisorClient::call().",
           "#pragma once", "", "#include <array>", "#include <cstdint>", "#include <string>", "",
           '#include "macsim/msg/macsim_msgs.h"', "",
           "namespace macsim::client::supervisor {", "",
           "using Request = macsim_msgs::msg::dds_::SupervisorRequest_;",
           "using Vec3 = std::array<double, 3>;  ///< x, y, z (m, m/s, N, ... as the operation says)",
           "using Quat = std::array<double, 4>;  ///< x, y, z, w (ROS order)",
           "using Rgba = std::array<float, 4>;   ///< each in [0, 1]",
           "inline constexpr Quat kIdentity{0, 0, 0, 1};", ""]
    for op in operations:
        doc = op_doc(op)
        out.extend(wrap(f"{op.const} ({op.code}). {doc}", 100, "/// "))
        out.extend(wrap_call(f"Request {op.name}(", signature(op, True).split(", "), ");"))
    out += ["", "}  // namespace macsim::client::supervisor", ""]
    return "\n".join(out)


def wrap_call(head, items, tail, width=100):
    """head + items joined by ", " + tail, broken after commas and aligned as clang-format does."""
    lines, line = [], head
    for i, item in enumerate(items):
        text = item + ("," if i + 1 < len(items) else tail)
        if line != head and not line.endswith(" ") and len(line) + 1 + len(text) > width:
            lines.append(line)
            line = " " * len(head) + text
        else:
            line += ("" if line == head or line.endswith("(") else " ") + text
    if not items:
        line += tail
    lines.append(line)
    return lines


def client_source(operations):
    out = [f"// {HEADER_NOTE}", '#include "macsim/client/supervisor_requests.h"', "",
           '#include "macsim/dds/convert.h"', "",
           "namespace macsim::client::supervisor {", "",
           "namespace mm = macsim_msgs::msg::dds_;", "namespace gm = geometry_msgs::msg::dds_;", "",
           "namespace {", "",
           "gm::Point_ point(const Vec3& v) { return dds::point(v[0], v[1], v[2]); }",
           "gm::Vector3_ vector(const Vec3& v) { return dds::vector3(v[0], v[1], v[2]); }",
           "gm::Quaternion_ quaternion(const Quat& q) { return dds::quaternion(q[0], q[1], q[2], q[3]); }",
           "", "}  // namespace", ""]
    for op in operations:
        out.extend(wrap_call(f"Request {op.name}(", signature(op, False).split(", "), ") {"))
        out.append("  mm::SupervisorOperation_ op;")
        if op.arg_type == "none":
            out.append(f"  op.{op.member}(false);")
        else:
            out.append(f"  mm::{op.arg_type} a;")
            for p in op.params:
                if p.kind == "vec3" and p.field.idl_type == "Vector3_":
                    value = f"vector({p.name})"
                elif p.kind == "vec3":
                    value = f"point({p.name})"
                elif p.kind == "quat":
                    value = f"quaternion({p.name})"
                else:
                    value = p.name
                target = f"a.{p.field.name}()" if p.sub else "a"
                setter = p.sub if p.sub else p.field.name
                out.append(f"  {target}.{setter}({value});")
            out.append(f"  op.{op.member}(a);")
        out.append(f"  op._d(mm::{op.const});")
        out.append("  Request r;")
        out.append("  r.operation(std::move(op));")
        out.append("  return r;")
        out.append("}")
        out.append("")
    out += ["}  // namespace macsim::client::supervisor", ""]
    return "\n".join(out)


# --- The dispatch ---------------------------------------------------------------------------

def dispatch(operations):
    """The switch over the operations: each calls the hand-written ops::<name>(context,
    arguments) of dds_bridge/src/supervisor/supervisor_operations.h (ops::<name>(context) for an
    operation without arguments); what only reads; and each operation's name."""
    out = [f"// {HEADER_NOTE}",
           "// Included by supervisor_dispatch.cpp inside namespace macsim::generated.", ""]
    out.append("/// Runs the operation (ops::<its name>) against c.world; nullopt for an unknown one.")
    out.append("inline std::optional<Status> run_operation(ops::Context& c,")
    out.append("                                           const mm::SupervisorOperation_& op) {")
    out.append("  switch (op._d()) {")
    for op in operations:
        arg = "" if op.arg_type == "none" else f", op.{op.member}()"
        out.append(f"    case mm::{op.const}:")
        out.append(f"      return ops::{op.name}(c{arg});")
    out.append("  }")
    out.append("  return std::nullopt;")
    out.append("}")
    out.append("")
    # Reads by their names: what a session need not record (a snapshot saved is kept: a
    # later restore depends on it).
    reads = [op for op in operations
             if op.name.startswith(("get_", "list_", "find_")) or op.name in ("door_count", "state_hash")]
    out.append("/// False for an operation that only reads (a session need not record it).")
    out.append("inline bool changes_world(int32_t code) {")
    out.append("  switch (code) {")
    for op in reads:
        out.append(f"    case mm::{op.const}:")
    out.append("      return false;")
    out.append("  }")
    out.append("  return true;")
    out.append("}")
    out.append("")
    out.append("/// The operation's name (e.g. \"set_density\"), or nullptr for an unknown code.")
    out.append("inline const char* name_of(int32_t code) {")
    out.append("  switch (code) {")
    for op in operations:
        out.append(f"    case mm::{op.const}:")
        out.append(f"      return \"{op.name}\";")
    out.append("  }")
    out.append("  return nullptr;")
    out.append("}")
    out.append("")
    return "\n".join(out)


# --- Python ---------------------------------------------------------------------------------

def cpp_string(text):
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def python_defs(operations):
    out = [f"// {HEADER_NOTE}",
           "// The Supervisor's methods, one .def per operation (not those marked python=manual).",
           "// Included by supervisor.cpp in the chain of py::class_<S> calls."]
    for op in operations:
        if op.manual_python:
            continue
        params = op.py_params()
        lambda_params = ", ".join(["S& s"] + [
            f"{CPP_TYPES[p.kind].replace('const Vec3&', 'const sv::Vec3&').replace('const Quat&', 'const sv::Quat&').replace('const Rgba&', 'const sv::Rgba&')} {p.name}"
            for p in params])
        call = f"s.call(sv::{op.name}({', '.join(p.name for p in op.cpp_params())}))"
        body = f"return {call}.{op.replies[0]}();" if op.replies else f"{call};"
        args = []
        for p in params:
            arg = f'py::arg("{p.name}")'
            if p.py_default is not None:
                arg += f" = {default_value(p.py_default, p.kind, 'pybind')}"
            args.append(arg)
        doc = op_doc(op, python=True) or op.name.replace("_", " ").capitalize() + "."
        pieces = [f'"{op.name}"', f"[]({lambda_params}) {{ {body} }}"] + args + [cpp_string(doc)]
        out.append(f"    .def({', '.join(pieces)})")
    out.append("")
    return "\n".join(out)


def pyi_methods(operations):
    out = []
    for op in operations:
        if op.manual_python:
            continue
        params = ["self"]
        for p in op.py_params():
            text = f"{p.name}: {PYI_TYPES[p.kind]}"
            if p.py_default is not None:
                text += f" = {default_value(p.py_default, p.kind, 'pyi')}"
            params.append(text)
        result = REPLY_PYI[op.replies[0]] if op.replies else "None"
        head = f"    def {op.name}({', '.join(params)}) -> {result}:"
        if len(head) > 100:
            out.append(f"    def {op.name}(")
            out.extend(f"            {p}," for p in params)
            out.append(f"    ) -> {result}:")
        else:
            out.append(head)
        doc = op_doc(op, python=True)
        if doc:
            doc_lines = wrap(doc, 92, "        ")
            doc_lines[0] = '        """' + doc_lines[0].strip()
            doc_lines[-1] += '"""'
            out.extend(doc_lines)
        else:
            out.append("        ...")
    return "\n".join(out)


def pyi(template, operations):
    marker = "    # @SUPERVISOR_OPERATIONS@"
    text = Path(template).read_text()
    if marker not in text:
        raise IdlError(f"{template}: no line '{marker.strip()}'")
    text = "\n".join(line for line in text.split("\n") if not line.startswith("#@"))
    note = f"# {HEADER_NOTE.replace('; do not', ' and dds_bridge/python/macsim/_macsim.pyi.in; do not')}"
    return note + "\n" + text.replace(marker, pyi_methods(operations))


# --- The reference ---------------------------------------------------------------------------

def doc_table(operations, structs):
    out = ["# Supervisor operations", "",
           f"<!-- {HEADER_NOTE} -->", "",
           "One request (`SupervisorRequest_`) carries one operation: the discriminator of the "
           "union `SupervisorOperation_` is the operation's code, its member the arguments. "
           "The reply (`SupervisorReply_`) carries `code` (`ERR_*`), `message` and the fields "
           "listed. Builders: `macsim::client::supervisor::<op>()` (C++), "
           "`macsim.Supervisor.<op>()` (Python).", "",
           "| operation | code | what it does | arguments (IDL struct: fields) | reply fields |",
           "|---|---|---|---|---|"]
    for op in operations:
        if op.arg_type == "none":
            arguments = "none"
        else:
            fields = []
            for f in structs[op.arg_type]:
                text = f"`{f.name}` ({f.idl_type}{'[%d]' % f.array if f.array else ''})"
                if f.comment:
                    text += f": {f.comment}"
                fields.append(text)
            arguments = f"`{op.arg_type}`: " + "; ".join(fields)
        replies = ", ".join(f"`{r}`" for r in op.replies) or "-"
        if op.reply_description:
            replies += f": {op.reply_description}"
        row = [f"`{op.name}`", f"{op.code} (`{op.const}`)", sentence(op.description), arguments,
               replies]
        cells = [c.replace("|", "\\|").replace("<", "&lt;").replace(">", "&gt;") for c in row]
        out.append("| " + " | ".join(cells) + " |")
    out.append("")
    return "\n".join(out)


def write(path, text):
    path = Path(path)
    if path.exists() and path.read_text() == text:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("idl")
    for option in ("client-header", "client-source", "dispatch", "python", "pyi-template", "pyi",
                   "doc"):
        parser.add_argument(f"--{option}" if option.startswith("pyi") else f"--out-{option}",
                            dest=option.replace("-", "_"))
    args = parser.parse_args()
    try:
        operations, structs = parse_idl(args.idl)
        if args.client_header:
            write(args.client_header, client_header(operations))
        if args.client_source:
            write(args.client_source, client_source(operations))
        if args.dispatch:
            write(args.dispatch, dispatch(operations))
        if args.python:
            write(args.python, python_defs(operations))
        if args.pyi:
            write(args.pyi, pyi(args.pyi_template, operations))
        if args.doc:
            write(args.doc, doc_table(operations, structs))
    except IdlError as e:
        print(f"generate_operations: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
