"""The package as a whole: every public binding exercised by this suite, the type stubs
matching the runtime and accepted by mypy, docs/python.md's examples running, the errc table
complete, and the package importable after the documented install (MOTIONBUS_PY_INSTALLED)."""

import ast
import os
import pathlib
import re
import subprocess
import sys
from typing import Dict, Set

import pytest

import motionbus
from motionbus import biss, crc, devices, modbus, tformat
from motionbus.devices import absys, sm_unit, ts5700n8500

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
PKG = pathlib.Path(motionbus.__file__).resolve().parent
MODULES = {"": motionbus, "crc": crc, "tformat": tformat, "modbus": modbus, "biss": biss,
           "devices/ts5700n8500": ts5700n8500, "devices/sm_unit": sm_unit, "devices/absys": absys}


def stub_names(path: pathlib.Path) -> Dict[str, Set[str]]:
    """Top-level names of a stub, and each class's members."""
    tree = ast.parse(path.read_text())
    out: Dict[str, Set[str]] = {"": set()}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            out[""].add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out[""].add(node.target.id)
        elif isinstance(node, ast.Assign):
            out[""].update(t.id for t in node.targets if isinstance(t, ast.Name))
        elif isinstance(node, ast.ImportFrom):
            out[""].update(a.asname for a in node.names if a.asname and a.asname == a.name)
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef) and not item.name.startswith("__"):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    members.add(item.target.id)
                elif isinstance(item, ast.Assign):
                    members.update(t.id for t in item.targets if isinstance(t, ast.Name))
            out[node.name] = members
    return out


def public(obj: object) -> Set[str]:
    return {n for n in dir(obj) if not n.startswith("_")}


@pytest.mark.parametrize("name", sorted(MODULES))
def test_stubs_match_runtime(name: str) -> None:
    mod = MODULES[name]
    stub = stub_names(PKG / f"{name or '__init__'}.pyi")
    runtime = set(mod.__all__)
    declared = stub[""] - {"BytesLike", "Layouts", "__all__", "__version__", "annotations"}
    assert runtime == declared, f"{name}: only in the runtime {runtime - declared}, only in the stub {declared - runtime}"
    for cls_name in runtime:
        cls = getattr(mod, cls_name)
        if isinstance(cls, type) and cls_name in stub and not issubclass(cls, (int, BaseException)):
            members = public(cls) - {"mro"}
            if cls.__module__.startswith("motionbus."):  # pure Python: instance attributes too
                assert members <= stub[cls_name], f"{name}.{cls_name}: {members - stub[cls_name]}"
            else:
                assert members == stub[cls_name], f"{name}.{cls_name}: {members ^ stub[cls_name]}"


def test_every_binding_is_exercised() -> None:
    text = "\n".join(p.read_text() for p in HERE.glob("test_*.py")
                     if p.name not in ("test_api.py", "test_bad_input.py"))
    text += (ROOT / "docs" / "python.md").read_text()
    missing = []
    for name, mod in MODULES.items():
        for n in mod.__all__:
            obj = getattr(mod, n)
            result_type = obj in list(motionbus._motionbus._result_classes)
            if not result_type and not re.search(rf"\b{re.escape(n)}\b", text):
                missing.append(f"{name}.{n}")
            if isinstance(obj, type) and not issubclass(obj, (int, BaseException)):
                missing += [f"{name}.{n}.{m}" for m in public(obj) - {"mro"}
                            if not re.search(rf"\.{re.escape(m)}\b", text)]
    assert not missing, "bindings no test exercises: " + ", ".join(missing)


def test_errc_table_is_complete() -> None:
    names = {int(e): e.name for e in motionbus.Errc}
    for v in range(256):
        known = motionbus._motionbus._errc_name(v) != "unknown"
        assert known == (v in names), f"errc {v}: in the header but not in the binding's table"
    assert motionbus.DecodeError(4).name == "crc_mismatch"


def examples() -> list:
    text = (ROOT / "docs" / "python.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, re.S)


@pytest.mark.parametrize("index", range(3))
def test_docs_examples_run(index: int, capsys: pytest.CaptureFixture) -> None:
    code = examples()[index]
    exec(compile(code, f"docs/python.md example {index}", "exec"), {"__name__": "example"})
    assert capsys.readouterr().out.strip()


def test_stubs_accepted_by_mypy(tmp_path: pathlib.Path) -> None:
    for i, code in enumerate(examples()):
        (tmp_path / f"example_{i}.py").write_text(code)
    (tmp_path / "wrong.py").write_text("from motionbus import tformat\ntformat.decode_response(5)\n")
    env = dict(os.environ, MYPYPATH=str(PKG.parent))
    cmd = [sys.executable, "-m", "mypy", "--strict", "--no-error-summary", "--cache-dir",
           str(tmp_path / "cache")]
    ok = subprocess.run(cmd + [str(p) for p in sorted(tmp_path.glob("example_*.py"))],
                        env=env, capture_output=True, text=True, cwd=tmp_path)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    bad = subprocess.run(cmd + [str(tmp_path / "wrong.py")], env=env, capture_output=True, text=True,
                         cwd=tmp_path)
    assert bad.returncode != 0 and "decode_response" in bad.stdout  # the stubs do type arguments


def test_installed_copy() -> None:
    where = os.environ.get("MOTIONBUS_PY_INSTALLED")
    if not where:
        pytest.skip("run by the ctest entry python_install")
    assert PKG.is_relative_to(pathlib.Path(where).resolve())
    assert (PKG / "py.typed").exists() and (PKG / "__init__.pyi").exists()
    assert motionbus.__version__.count(".") == 2 and devices.__all__
