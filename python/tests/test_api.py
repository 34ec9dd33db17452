"""The stubs describe the extension, and every public function has a docstring."""

import ast
import inspect
import pathlib

import manyworlds
from manyworlds import _core, benchmarks, env, manipulation, vector


def stub_names():
    path = pathlib.Path(manyworlds.__file__).with_name("_core.pyi")
    tree = ast.parse(path.read_text())
    names, members = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            names.add(node.name)
            members[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        elif isinstance(node, ast.FunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
    return names, members


def test_stubs_cover_the_extension():
    names, members = stub_names()
    public = {n for n in dir(_core) if not n.startswith("_")}
    assert public <= names, public - names
    for cls in ("Env", "Executor", "Rng"):
        attrs = {n for n in dir(getattr(_core, cls)) if not n.startswith("_")}
        assert attrs <= members[cls], (cls, attrs - members[cls])


def test_every_public_callable_has_a_docstring():
    missing = []
    for module in (manyworlds, env, vector, benchmarks, manipulation):
        for name, obj in vars(module).items():
            if name.startswith("_") or getattr(obj, "__module__", "").split(".")[0] != "manyworlds":
                continue
            if inspect.isfunction(obj) or inspect.isclass(obj):
                if not inspect.getdoc(obj):
                    missing.append(f"{module.__name__}.{name}")
                if inspect.isclass(obj):
                    for attr, member in vars(obj).items():
                        if attr.startswith("_") or not (inspect.isfunction(member) or isinstance(member, property)):
                            continue
                        if not inspect.getdoc(member):
                            missing.append(f"{module.__name__}.{name}.{attr}")
    assert not missing, missing
    for name in ("Env", "Executor"):
        for attr, member in vars(getattr(_core, name)).items():
            if not attr.startswith("_") and callable(member) and not isinstance(member, property):
                assert member.__doc__, f"_core.{name}.{attr}"
