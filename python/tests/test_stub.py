"""The stub (gridplan/__init__.pyi) declares exactly the module's public names, and each
class's public members."""

import ast
import inspect
from pathlib import Path

import gridplan

STUB = Path(gridplan.__file__).with_name("__init__.pyi")


def stub_names():
    """Top-level public names, and each class's public members, declared in the stub."""
    tree = ast.parse(STUB.read_text())
    names, members = set(), {}
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
        if isinstance(node, ast.ClassDef):
            declared = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    declared.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    declared.add(item.target.id)
            members[node.name] = {n for n in declared if not n.startswith("_")}
    return {n for n in names if not n.startswith("_")}, members


def module_names():
    return {
        name
        for name, value in vars(gridplan).items()
        if not name.startswith("_") and not inspect.ismodule(value)
    }


def class_members(cls):
    """Public members a class adds (instance attributes of exceptions included)."""
    if issubclass(cls, BaseException):
        instance = cls("message")
        inherited = set(dir(Exception("message"))) | set(dir(ValueError("message")))
        return {n for n in dir(instance) if not n.startswith("_") and n not in inherited}
    return {n for n in dir(cls) if not n.startswith("_")}


def test_stub_declares_every_public_name_and_no_other():
    names, _ = stub_names()
    assert names == module_names()
    assert names == set(gridplan.__all__)


def test_stub_declares_every_class_member():
    _, members = stub_names()
    for name, declared in members.items():
        cls = getattr(gridplan, name)
        assert declared == class_members(cls), name
