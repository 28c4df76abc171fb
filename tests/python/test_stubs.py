"""The type stubs (_macsim.pyi) match the module: every public class, method, property,
function and constant the extension has is in the stubs with the same parameters, and nothing
more."""

import ast
import inspect
from pathlib import Path

import macsim
import macsim._macsim as extension

STUBS = ast.parse((Path(extension.__file__).parent / "_macsim.pyi").read_text())


def stub_classes():
    classes = {}
    for node in STUBS.body:
        if isinstance(node, ast.ClassDef):
            members = {}
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    static = any(isinstance(d, ast.Name) and d.id == "staticmethod"
                                 for d in item.decorator_list)
                    members[item.name] = [a.arg for a in item.args.args[0 if static else 1:]] + \
                                         [a.arg for a in item.args.kwonlyargs]
                elif isinstance(item, ast.AnnAssign):
                    members[item.target.id] = None
            classes[node.name] = members
    return classes


def stub_constants():
    return {node.target.id for node in STUBS.body
            if isinstance(node, ast.AnnAssign) and node.target.id.isupper()}


def stub_functions():
    return {node.name: [a.arg for a in node.args.args] for node in STUBS.body
            if isinstance(node, ast.FunctionDef)}


def runtime_parameters(function):
    """The parameter names pybind11 documents in the first line of a method's docstring."""
    signature = function.__doc__.splitlines()[0]
    inside = signature[signature.index("(") + 1:signature.rindex(")")]
    parts, depth, current = [], 0, ""
    for char in inside:  # split at the commas outside brackets (defaults may be tuples)
        depth += char in "([{" and 1 or char in ")]}" and -1 or 0
        if char == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += char
    parts.append(current)
    names = [part.split(":")[0].strip() for part in parts]
    return [name for name in names if name and name not in ("self", "*")]


def test_every_class_and_constant_of_the_module_is_in_the_stubs():
    classes = stub_classes()
    runtime = {n for n, v in vars(extension).items() if inspect.isclass(v) and not n.startswith("_")}
    assert runtime == set(classes)
    constants = {n for n, v in vars(extension).items() if n.isupper() and isinstance(v, int)}
    assert constants == stub_constants()
    functions = {n: v for n, v in vars(extension).items()
                 if inspect.isbuiltin(v) and not n.startswith("_")}
    assert set(functions) == set(stub_functions())
    for name, function in functions.items():
        assert runtime_parameters(function) == stub_functions()[name], name
        assert function.__doc__, name
    assert set(macsim.__all__) == runtime | constants | set(functions)


def test_every_member_is_in_the_stubs_with_its_parameters():
    for name, members in stub_classes().items():
        cls = getattr(extension, name)
        if issubclass(cls, BaseException):
            continue  # exceptions: their attributes are BaseException's or set per instance
        public = {m for m in dir(cls) if not m.startswith("_")}
        assert public == set(members) - {"__init__"}, name
        for member, parameters in members.items():
            attribute = getattr(cls, member)
            if parameters is None or isinstance(attribute, property):
                continue
            assert runtime_parameters(attribute) == parameters, f"{name}.{member}"


def test_every_call_is_documented():
    for name in stub_classes():
        cls = getattr(extension, name)
        assert cls.__doc__, name
        for member in dir(cls):
            if not member.startswith("_") and callable(getattr(cls, member)):
                assert getattr(cls, member).__doc__, f"{name}.{member}"
