"""Generated C and the build cache carry no one else's code: a scene's name (and every other
text of the scene) reaches the exported C and README only as an escaped literal, the exported
example compiles and runs whatever the name; the build cache loads only libraries it built,
in a folder only its user can write, and clears only its own entries."""
from __future__ import annotations

import json
import os
import re
import stat
import subprocess
import tomllib
import warnings
from dataclasses import replace
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.mechanism import codegen
from symcable.api import export
from symcable.scene import load_scene

SEED001 = Path(sc.__file__).parent / "data" / "seed001.toml"

#: payloads that would close the old C comment and run code when the example is built and run
PAYLOAD = '*/ int x = system("touch PWNED"); /*'
CONSTRUCTOR = ('*/ __attribute__((constructor)) static void pwn(void) '
               '{ system("touch PWNED"); } /*')
#: a name a scene file may hold (printable, at most 200 characters) with both payloads,
#: comment markers, quotes, a backslash, trigraphs and non-ASCII characters
PRINTABLE = 'x */ y /* "q" \\ ??/ ??= Ω 🌊 Ω1 ' + PAYLOAD + " " + CONSTRUCTOR
#: every kind of character the escaping must handle, in one name: PRINTABLE with newlines,
#: a carriage return, control characters and digits after escaped bytes (a Scene built in
#: Python, which no scene file can hold)
COMBINED = PRINTABLE + ' line\nbreak\rreturn \t\x01\x1b\x7f controls, 3 digits: \n123 Ω777'
#: a line type name with the same kind of payload
TYPE_NAME = "chain */ int y; /* Ω"


def _scene(name: str, segments: int = 2, type_name: str = "chain"):
    """The built-in planar seed-001 scene with ``name``, few segments and the line type
    renamed to ``type_name``."""
    with open(SEED001, "rb") as fh:
        d = tomllib.load(fh)
    d["name"] = name
    d["line_types"] = {type_name: d["line_types"]["chain"]}
    for s in d["sections"]:
        s["segments"] = segments
        s["type"] = type_name
    return load_scene(d)


def _c_literal_value(lit: str) -> bytes:
    """The bytes of a C string literal using only plain characters and escapes ``\\ooo``."""
    assert lit[0] == lit[-1] == '"'
    body, out, i = lit[1:-1], bytearray(), 0
    while i < len(body):
        if body[i] == "\\":
            assert re.fullmatch(r"[0-7]{3}", body[i + 1:i + 4]), body[i:i + 4]
            out.append(int(body[i + 1:i + 4], 8))
            i += 4
        else:
            assert 0x20 <= ord(body[i]) < 0x7F and body[i] not in '"\\?', body[i]
            out.append(ord(body[i]))
            i += 1
    return bytes(out)


def _readme_name(readme: str) -> str:
    m = re.search(r"^Scene name \(a JSON string; `SCENE_NAME` in `\w+_data\.h`\): `([^`\n]*)`$",
                  readme, re.M)
    assert m, readme[:400]
    return json.loads(m.group(1))


def _printable(text: str) -> bool:
    return all(ch == "\n" or 0x20 <= ord(ch) < 0x7F for ch in text)


@pytest.mark.parametrize("name", ["*/", "/*", '"', "\\", "??/", "a\nb", "a\rb", "\x01\x1f\x7f",
                                  "Ω", "🌊", "\\0123", "\n0", PAYLOAD, CONSTRUCTOR, COMBINED])
def test_escaped_literals_round_trip(name):
    """The C literal holds only printable ASCII other than ``"``, ``\\`` and ``?``, and octal
    escapes of exactly three digits, and decodes to the name's UTF-8 bytes; the Markdown
    literal is ASCII without backticks and decodes (JSON) to the name."""
    lit = export._c_string(name)
    assert _c_literal_value(lit) == name.encode("utf-8")
    assert "??" not in lit and "\n" not in lit
    md = export._md_literal(name)
    assert md[0] == md[-1] == "`" and "`" not in md[1:-1] and _printable(md) and "\n" not in md
    assert json.loads(md[1:-1]) == name


@pytest.mark.parametrize("name", [PRINTABLE, COMBINED], ids=["scene-file", "python"])
def test_export_hostile_names_compile_run_and_round_trip(tmp_path, name):
    """A scene named with two code-injection payloads and awkward characters (through
    load_scene, and with control characters too, as a Scene built in Python may be), whose
    line type is named with a third: the exported C compiles (-O0, the README's command
    otherwise), runs, creates no PWNED file, and prints the name back byte for byte; neither
    name appears raw in any file, and the README gives the name as a JSON string."""
    out = tmp_path / "c"
    scene = _scene(PRINTABLE, type_name=TYPE_NAME)
    if name != PRINTABLE:
        scene = replace(scene, name=name)
    assert scene.name == name
    paths = export.export_scene(scene, out, stem="hostile_scene2")
    assert {p.name for p in paths} == {"hostile_scene2.c", "hostile_scene2.h",
                                       "hostile_scene2_data.h", "main.c", "README.md"}
    for p in paths:
        text = p.read_text(encoding="utf-8")
        assert _printable(text), p.name  # no raw non-ASCII or control characters anywhere
        assert "PWNED" not in text or p.name in ("hostile_scene2_data.h", "README.md"), p.name
        assert TYPE_NAME not in text and "int y;" not in text, p.name
    data = (out / "hostile_scene2_data.h").read_text()
    m = re.search(r'^static const char SCENE_NAME\[\] = ("[^"\n]*");$', data, re.M)
    assert m and _c_literal_value(m.group(1)) == name.encode("utf-8")
    rest = data.replace(m.group(0), "")  # the payloads are inside the literal only
    assert "PWNED" not in rest and rest.count("/*") == rest.count("*/") == 1
    readme = (out / "README.md").read_text()
    assert _readme_name(readme) == name
    assert "PWNED" not in readme.replace(export._md_literal(name), "")

    cc = codegen.compiler()
    assert cc is not None, "no C compiler on this machine"
    build = subprocess.run([cc, "-O0", "main.c", "hostile_scene2.c", "-lm", "-o", "example"],
                           cwd=out, capture_output=True, text=True, timeout=120)
    assert build.returncode == 0, build.stderr[-2000:]
    run = subprocess.run([str(out / "example")], cwd=out, capture_output=True, timeout=60)
    assert run.returncode == 0, run.stderr[-2000:]
    assert not (out / "PWNED").exists() and not list(tmp_path.rglob("PWNED"))
    assert run.stdout.startswith(b"scene: " + name.encode("utf-8") + b"\nstatic: ")
    assert b"dynamics: 100 steps done" in run.stdout


@pytest.mark.parametrize("stem", ["", "1abc", "_abc", "a b", "a-b", "../x", "x/y", "x;", "x\n",
                                  "Ω", "a.c", None, 3])
def test_export_rejects_stems_that_are_not_identifiers(tmp_path, stem):
    """A stem other than a letter then letters, digits or underscores is refused, naming the
    value and what is allowed, before anything is written."""
    with pytest.raises(sc.SymcableError, match=r"^stem = .*: must be a letter followed by "
                                               r"letters, digits or underscores"):
        export.export_scene(_scene("plain"), tmp_path / "c", stem=stem)
    assert not (tmp_path / "c").exists()


# --------------------------------------------------------------------------- the build cache

def _f():
    x = ca.SX.sym("x")
    return ca.Function("sq_security", [x], [x ** 2], ["x"], ["y"])


@pytest.fixture
def cache(monkeypatch, tmp_path):
    """A build cache folder of this test's own (mode 0700), nothing loaded, nothing warned."""
    folder = tmp_path / "cache"
    folder.mkdir(mode=0o700)
    folder.chmod(0o700)
    monkeypatch.setenv("SYMCABLE_CACHE_DIR", str(folder))
    monkeypatch.setattr(codegen, "_loaded", {})
    monkeypatch.setattr(codegen, "_warned", set())
    return folder


@pytest.fixture(scope="module")
def evil(tmp_path_factory):
    """(a shared library outside any cache whose constructor writes a marker file, marker)."""
    folder = tmp_path_factory.mktemp("evil")
    marker = folder / "MARKER"
    src = folder / "evil.c"
    src.write_text('#include <stdio.h>\n__attribute__((constructor)) static void pwn(void) {\n'
                   f'  FILE *f = fopen({json.dumps(str(marker))}, "w"); if (f) fclose(f);\n}}\n')
    lib = folder / "evil.so"
    proc = subprocess.run([codegen.compiler(), "-shared", "-fPIC", str(src), "-o", str(lib)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    return lib, marker


def _plant(folder: Path, library: str, digest: str) -> str:
    key = codegen._key([_f()], codegen.compiler())[0]
    (folder / f"{key}.json").write_text(json.dumps({"key": key, "library": library,
                                                     "sha256": digest}))
    return key


def _check_rebuilt(folder: Path, evil_lib: Path, marker: Path) -> None:
    lib = codegen.compile_functions([_f()])
    assert codegen.last_build["action"] == "compiled"
    assert Path(codegen.last_build["library"]).parent == folder.resolve()
    assert not Path(codegen.last_build["library"]).is_symlink()
    assert float(lib["sq_security"](3.0)) == 9.0
    assert not marker.exists()
    assert codegen._valid_entry(folder.resolve(), codegen.last_build["key"]) is not None


def test_record_naming_a_library_outside_the_folder_is_rebuilt(cache, evil):
    """A record whose library is an absolute path elsewhere, with that library's correct
    digest: not loaded (its constructor never runs), rebuilt in the folder instead."""
    lib, marker = evil
    _plant(cache, str(lib), codegen._digest(lib))
    _check_rebuilt(cache, lib, marker)


def test_record_naming_a_library_through_dotdot_is_rebuilt(cache, evil):
    lib, marker = evil
    _plant(cache, os.path.relpath(lib, cache), codegen._digest(lib))
    assert ".." in json.loads(next(cache.glob("*.json")).read_text())["library"]
    _check_rebuilt(cache, lib, marker)


def test_symlinked_library_is_rebuilt(cache, evil):
    """A library with the name the key and digest allow, but a symbolic link to a library
    elsewhere (whose digest the record gives): not loaded, rebuilt; the target untouched."""
    lib, marker = evil
    digest = codegen._digest(lib)
    key = codegen._key([_f()], codegen.compiler())[0]
    (cache / f"{key}-{digest[:16]}.so").symlink_to(lib)
    _plant(cache, f"{key}-{digest[:16]}.so", digest)
    _check_rebuilt(cache, lib, marker)
    assert codegen._digest(lib) == digest


def test_library_of_another_user_is_not_loaded(cache, monkeypatch):
    """A library the cache built but now owned by someone else (the current user's id
    changed under it): not loaded."""
    codegen.compile_functions([_f()])
    key = codegen.last_build["key"]
    assert codegen._valid_entry(cache, key) is not None
    monkeypatch.setattr(codegen, "_uid", lambda: os.getuid() + 1)
    assert codegen._valid_entry(cache, key) is None


def _untrusted(folder: Path, match: str):
    """use_codegen and compile_functions with the build cache in ``folder``: one warning
    naming the folder and ``match``, then the virtual machine, nothing written."""
    before = sorted(os.listdir(folder))
    f = _f()
    with pytest.warns(codegen.CodegenWarning, match=re.escape(str(folder)) + ".*" + match) as rec:
        assert codegen.use_codegen(True) is False
    assert len(rec) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # once per folder and process
        assert codegen.use_codegen(None) is False
        assert codegen.use_codegen(None, [f]) is False
        got = codegen.compile_functions([f])
        assert got["sq_security"] is f and codegen.last_build["action"] == "vm"
        d = sc.load_scene(_scene_dict(4))
        vm = sc.solve_static(d, codegen=False)
        cg = sc.solve_static(d, codegen=True)
    assert not cg.stats["compiled"]
    np.testing.assert_array_equal(cg.positions, vm.positions)
    assert sorted(os.listdir(folder)) == before


def _scene_dict(segments):
    with open(SEED001, "rb") as fh:
        d = tomllib.load(fh)
    d["sections"][0]["segments"] = segments
    return d


@pytest.mark.parametrize("mode", [0o777, 0o775, 0o1777])
def test_folder_writable_by_others_is_not_used(monkeypatch, tmp_path, mode):
    folder = tmp_path / "shared"
    folder.mkdir()
    folder.chmod(mode)
    monkeypatch.setenv("SYMCABLE_CACHE_DIR", str(folder))
    monkeypatch.setattr(codegen, "_loaded", {})
    monkeypatch.setattr(codegen, "_warned", set())
    _untrusted(folder, "writable by its group or by others")
    assert stat.S_IMODE(folder.stat().st_mode) == mode  # not "repaired" behind the user's back


def test_symlink_to_a_shared_folder_is_not_used(monkeypatch, tmp_path):
    target = tmp_path / "shared"
    target.mkdir()
    target.chmod(0o777)
    link = tmp_path / "link"
    link.symlink_to(target)
    monkeypatch.setenv("SYMCABLE_CACHE_DIR", str(link))
    monkeypatch.setattr(codegen, "_loaded", {})
    monkeypatch.setattr(codegen, "_warned", set())
    _untrusted(link, "writable by its group or by others")
    assert os.listdir(target) == []


def test_folder_of_another_user_is_not_used(cache, monkeypatch):
    """A folder owned by someone else (as seen by a current user with another id; works
    as root and as any user): warning, the virtual machine."""
    uid = os.getuid()
    monkeypatch.setattr(codegen, "_uid", lambda: uid + 1)
    _untrusted(cache, f"owned by uid {uid}, not by the current user")


def test_new_folder_is_created_private(monkeypatch, tmp_path):
    """A missing cache folder is created with mode 0700 whatever the umask, and used."""
    folder = tmp_path / "xdg" / "symcable"
    monkeypatch.delenv("SYMCABLE_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setattr(codegen, "_loaded", {})
    old = os.umask(0o002)
    try:
        assert codegen.cache_dir() == folder
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            codegen.compile_functions([_f()])
    finally:
        os.umask(old)
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert codegen.last_build["action"] == "compiled"
    assert Path(codegen.last_build["library"]).parent == folder.resolve()


def test_clear_cache_removes_only_its_own_entries(cache):
    """clear_cache and cache_info see the cache's records, libraries, temporary files and
    build folders, and leave every other file and folder alone."""
    codegen.compile_functions([_f()])
    foreign = {"notes.json": b"{}", "other.so": b"\x7fELF", "README": b"mine",
               "ABCDEF0123456789ABCDEF0123456789.json": b"{}", ".tmp-x.txt": b"x"}
    for name, data in foreign.items():
        (cache / name).write_bytes(data)
    (cache / "foo").mkdir()
    (cache / "foo" / "keep.json").write_text("{}")
    (cache / ".tmp-abc_123.json").write_text("{")
    (cache / ".tmp-k9z_0q1x.so").write_bytes(b"partial")
    (cache / ".build-q1w2e3r4").mkdir()
    (cache / ".build-q1w2e3r4" / "lib.so").write_bytes(b"partial")
    own = {p.name for p in cache.iterdir()} - set(foreign) - {"foo"}
    assert len(own) == 5  # record, library, two temporary files, a build folder
    info = codegen.cache_info()
    assert info["entries"] == 1
    lib = Path(codegen.last_build["library"])
    assert info["bytes"] == (lib.stat().st_size + len("{") + len(b"partial")
                             + (cache / f"{codegen.last_build['key']}.json").stat().st_size)
    assert codegen.clear_cache() == 1
    assert {p.name for p in cache.iterdir()} == set(foreign) | {"foo"}
    assert all((cache / n).read_bytes() == d for n, d in foreign.items())
    assert (cache / "foo" / "keep.json").read_text() == "{}"
    assert codegen.cache_info()["entries"] == 0
