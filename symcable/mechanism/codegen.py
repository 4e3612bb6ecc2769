"""Generated C: the only place in symcable that writes C or calls a compiler (with
:mod:`.background_build`, which compiles in a process of its own; :mod:`symcable.api.export`
uses it to write the C of a whole scene).

CasADi writes C for a group of Functions; the system C compiler turns it into a shared
library in a build cache; ``casadi.external`` loads it back as Functions with the same
names and signatures, which the solvers call exactly as they call the virtual machine's.

The cache
---------
* Folder: ``$SYMCABLE_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/symcable`` (default
  ``~/.cache/symcable``), created with mode 0700. ``symcable cache clear`` removes its
  entries (see *Trust* below) and nothing else.
* Key: SHA-256 of the serialised Functions (``Function.serialize``: the whole expression
  graph), the CasADi version, the compiler and its flags. Parameters (end positions,
  current, excitation, the static state of a linearisation) are *inputs* of the Functions,
  not constants, so scenes that differ only in them share one library.
* Entry: ``<key>.json`` names the library ``<key>-<digest>.so`` and records its SHA-256.
  Both are written to a temporary file and renamed into place (atomic on POSIX), so several
  processes may build the same entry at once; whichever rename lands last wins, and both
  libraries are valid. A library whose digest does not match (truncated, damaged), or an
  entry that cannot be read, is rebuilt, never loaded.

Trust
-----
Loading a library runs its code, so the cache loads only what it built itself:

* The folder must be a directory owned by the current user and writable by nobody else
  (no group or other write bit); a symbolic link is judged by the folder it points to.
  Any other folder is not used: :func:`use_codegen` and :func:`compile_functions` fall back
  to the CasADi virtual machine (same results, slower) with one :class:`CodegenWarning` per
  folder and process, naming the folder and the reason.
* A record's library must be named ``<key>-<digest16>.so`` after the record's own key and
  the first 16 hexadecimal digits of its SHA-256, inside the folder (no other path), and be
  a regular file (not a symbolic link) owned by the current user whose SHA-256 matches the
  record's. Anything else is rebuilt, never loaded.
* The cache's own files are ``<key>.json`` (32 hexadecimal digits), ``<key>-<digest16>.so``
  and the temporary ``.tmp-*.json``, ``.tmp-*.so`` and ``.build-*`` of builds under way;
  :func:`clear_cache` and :func:`cache_info` remove and count those only.

Compiler: ``$CC`` if set, else the first of ``cc``, ``gcc``, ``clang`` on the PATH. When
none is found, :func:`use_codegen` warns once and every analysis falls back to the CasADi
virtual machine (same results, slower). Optimisation: by graph size (:data:`OPTIMISATION`),
or ``$SYMCABLE_CC_OPT`` (one of -O0, -O1, -O2, -O3, -Os) for every build: -O0 compiles
several times faster and runs slower (the test suite uses it: it checks what C computes,
not how fast).
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile
import threading
import time
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Sequence

import casadi as ca

from ..errors import SymcableError
from ..progress import notice
from . import background_build
from .fastcall import FastCall

__all__ = ["CodegenWarning", "FastCall", "cache_dir", "cache_info", "cached_only", "clear_cache",
           "compile_functions", "compiler", "export_sources", "graph_estimate", "graph_size",
           "use_codegen", "DEFAULT_MAX_SIZE", "FLAGS", "MAX_COMPILE_SIZE", "OPTIMISATION",
           "flags_for"]

#: compiler flags of cached libraries (part of the cache key). -O2: on the generated step
#: and Newton functions it is within a few % of -O3 and compiles faster.
FLAGS = ("-O2", "-fPIC", "-shared")
#: bump when the layout of generated code or of cache entries changes
FORMAT = 1
#: largest graph (characters of the serialised Functions, see :func:`graph_size`) that the
#: default ``codegen=None`` compiles. The C of a Function is written out straight-line, and
#: the C compiler's time grows faster than its length, while the gain per call stays a
#: constant factor; larger graphs run in the virtual machine unless asked (the compile times
#: against graph size behind this bound: the performance study, in the docs)
DEFAULT_MAX_SIZE = 5_000_000
#: the optimisation level by graph size (:func:`graph_size`): [(largest size, flag)]. Every
#: graph the default ``codegen=None`` compiles gets -O2 (FLAGS); larger ones, compiled only
#: when asked (``codegen=True``), get -O1, which runs as fast (gcc's time grows faster than
#: the C's length, and -O2 gains little on straight-line code), and -O0 only beyond
#: 10 DEFAULT_MAX_SIZE, where -O1 would take many minutes (compile and step times at each
#: level: the performance study, in the docs).
OPTIMISATION = ((DEFAULT_MAX_SIZE, "-O2"), (10 * DEFAULT_MAX_SIZE, "-O1"), (math.inf, "-O0"))
#: largest graph (:func:`graph_estimate`) compiled even when asked (``codegen=True``): the C
#: compiler's memory grows faster than the C's length, and beyond this it needs many GB and
#: many minutes; such Functions run in the virtual machine with a :class:`CodegenWarning`
MAX_COMPILE_SIZE = 20 * DEFAULT_MAX_SIZE
#: characters of a serialised graph per SX instruction or MX node, about (85 to 98 on the
#: statics, steps and outputs of cable3d lines): :func:`graph_estimate`'s factor
CHARS_PER_NODE = 90
_ENV_CACHE = "SYMCABLE_CACHE_DIR"
_ENV_OPT = "SYMCABLE_CC_OPT"
_OPT_LEVELS = ("-O0", "-O1", "-O2", "-O3", "-Os")
_ENV_DEFAULT = "SYMCABLE_CODEGEN"


class CodegenWarning(UserWarning):
    """Generated C was asked for (or is the default) but cannot be used here."""


# --------------------------------------------------------------------------- environment

_found: dict = {}


def compiler() -> str | None:
    """Path of the C compiler: ``$CC`` (its first word) if set, else ``cc``, ``gcc`` or
    ``clang`` from the PATH; None when there is none. Looked up once per (CC, PATH)."""
    key = (os.environ.get("CC"), os.environ.get("PATH"))
    if key not in _found:
        _found[key] = _find_compiler()
    return _found[key]


def _find_compiler() -> str | None:
    cc = os.environ.get("CC")
    if cc is not None:
        cc = cc.split()[0] if cc.strip() else ""
        return shutil.which(cc) if cc else None
    for name in ("cc", "gcc", "clang"):
        path = shutil.which(name)
        if path:
            return path
    return None


def cache_dir() -> Path:
    """The build cache folder as configured (``$SYMCABLE_CACHE_DIR``, else
    ``$XDG_CACHE_HOME/symcable`` or ``~/.cache/symcable``); created, mode 0700, on first use."""
    env = os.environ.get(_ENV_CACHE)
    if env:
        return Path(env).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "symcable"


_warned: set = set()

#: names of the cache's own files: records, libraries, temporary files and build folders
_RECORD = re.compile(r"[0-9a-f]{32}\.json")
_LIBRARY = re.compile(r"[0-9a-f]{32}-[0-9a-f]{16}\.so")
_TEMP = re.compile(r"\.tmp-[a-z0-9_]+\.(?:json|so)")
_BUILD = re.compile(r"\.build-[a-z0-9_]+")


def _uid() -> int | None:
    """The current user's id (None where the platform has none)."""
    return os.getuid() if hasattr(os, "getuid") else None


def _folder_problem(folder: Path) -> tuple[Path | None, str]:
    """(the folder with symbolic links resolved, "") when ``folder`` is fit to hold the cache,
    creating it with mode 0700 if it is missing; else (None, why not)."""
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.mkdir(folder, 0o700)
            os.chmod(folder, 0o700)  # the umask may have cleared bits of the mode; none added
        except FileExistsError:
            pass
        real = Path(os.path.realpath(folder))
        st = os.stat(real)
    except OSError as exc:
        return None, f"cannot be created or read ({exc.strerror or exc})"
    if not stat.S_ISDIR(st.st_mode):
        return None, "is not a directory"
    uid = _uid()
    if uid is not None and st.st_uid != uid:
        return None, f"is owned by uid {st.st_uid}, not by the current user (uid {uid})"
    if st.st_mode & 0o022:
        return None, (f"is writable by its group or by others (mode {stat.S_IMODE(st.st_mode):#o}; "
                      "the cache needs a folder only its owner can write, e.g. mode 0700)")
    return real, ""


def _trusted_folder(stacklevel: int = 3) -> Path | None:
    """The build cache folder (symbolic links resolved) when it is fit to use, else None
    after one :class:`CodegenWarning` per folder and process naming the folder and why."""
    folder = cache_dir()
    real, why = _folder_problem(folder)
    if real is None:
        tag = f"cache folder {folder}"
        if tag not in _warned:
            _warned.add(tag)
            warnings.warn(f"build cache {folder} {why}: not used; using the CasADi virtual machine "
                          "instead (same results, slower)", CodegenWarning, stacklevel=stacklevel)
    return real


def graph_estimate(functions: Sequence[ca.Function]) -> int:
    """About :func:`graph_size` without serialising (a large step's serialisation takes
    seconds and its length in memory; this, milliseconds): :data:`CHARS_PER_NODE` times the
    SX instructions and MX nodes of the Functions and of every Function they call, each
    counted once (other kinds, such as maps and linear solvers, as one node)."""
    seen = {}
    for f in functions:
        for g in (f, *f.find_functions()):
            seen[hash(g)] = g
    nodes = 0
    for g in seen.values():
        nodes += (g.n_instructions() if g.is_a("SXFunction") else
                  g.n_nodes() if g.is_a("MXFunction") else 1)
    return CHARS_PER_NODE * nodes


def graph_size(functions: Sequence[ca.Function], limit: float | None = None) -> int:
    """Size of Functions' graphs, every Function they call included: the length of their
    serialisation, characters (about proportional to the generated C). With ``limit``, a
    graph whose :func:`graph_estimate` exceeds twice the limit is not serialised: the
    estimate is returned (far above the limit either way)."""
    if limit is not None:
        est = graph_estimate(functions)
        if est > 2 * limit:
            return est
    return sum(len(f.serialize()) for f in functions)


def use_codegen(codegen: bool | None, functions=None) -> bool:
    """Resolve an analysis' ``codegen`` argument.

    ``None`` (the default of every analysis): generated C when a C compiler is found and
    ``functions`` (the Functions that would be compiled, or a callable returning their
    :func:`graph_size`, when given) are small enough that compiling them pays
    (:data:`DEFAULT_MAX_SIZE`), else the virtual machine, silently;
    ``SYMCABLE_CODEGEN=0`` in the environment makes the default the virtual machine (for
    one-off solves, where compiling a new model structure, seconds once, costs more than it
    saves). ``True``: generated C, or one :class:`CodegenWarning` and the virtual machine
    when there is no compiler. ``False``: the virtual machine. Where generated C would be
    used but the build cache folder is not fit (not the user's own, or writable by others:
    see the module's *Trust*), one :class:`CodegenWarning` per folder and the virtual machine.
    """
    if codegen is None:
        env = os.environ.get(_ENV_DEFAULT, "").strip().lower()
        if env in ("0", "false", "off", "no"):
            return False
        if compiler() is None:
            return False
        if functions is not None:
            size = functions() if callable(functions) else graph_size(functions,
                                                                      DEFAULT_MAX_SIZE)
            if size > DEFAULT_MAX_SIZE:
                return False
        return _trusted_folder(stacklevel=4) is not None
    if not isinstance(codegen, bool):
        raise SymcableError(f"codegen = {codegen!r}: must be True, False or None (automatic)")
    if codegen and compiler() is None:
        cc = os.environ.get("CC")
        where = f"CC = {cc!r} is not an executable" if cc is not None else "no cc, gcc or clang on the PATH"
        if where not in _warned:
            _warned.add(where)
            warnings.warn(f"codegen=True: no C compiler ({where}); using the CasADi virtual "
                          "machine instead (same results, slower)", CodegenWarning, stacklevel=3)
        return False
    return codegen and _trusted_folder(stacklevel=4) is not None


def _compiler_id(cc: str) -> str:
    try:
        out = subprocess.run([cc, "--version"], capture_output=True, text=True, timeout=30)
        return out.stdout.splitlines()[0] if out.stdout else cc
    except (OSError, subprocess.SubprocessError):
        return cc


_cc_ids: dict = {}


def flags_for(size: int) -> tuple:
    """The compiler flags for Functions of graph size ``size`` (:func:`graph_size`): FLAGS
    with the optimisation level of :data:`OPTIMISATION`, or of ``$SYMCABLE_CC_OPT``."""
    level = os.environ.get(_ENV_OPT, "").strip()
    if level and level not in _OPT_LEVELS:
        raise SymcableError(f"{_ENV_OPT} = {level!r}: must be one of {', '.join(_OPT_LEVELS)} "
                            "(or unset: by graph size)")
    level = level or next(flag for top, flag in OPTIMISATION if size <= top)
    return (level,) + tuple(f for f in FLAGS if not f.startswith("-O"))


def _key(functions: Sequence[ca.Function], cc: str) -> tuple[str, tuple]:
    """(cache key, compiler flags) of ``functions``."""
    h = hashlib.sha256()
    if cc not in _cc_ids:
        _cc_ids[cc] = _compiler_id(cc)
    graphs = [f.serialize() for f in functions]
    flags = flags_for(sum(len(g) for g in graphs))
    h.update(f"symcable-codegen {FORMAT}|casadi {ca.__version__}|{_cc_ids[cc]}|{' '.join(flags)}".encode())
    for f, g in zip(functions, graphs):
        h.update(f.name().encode())
        h.update(g.encode())
    return h.hexdigest()[:32], flags


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _write_atomic(path: Path, data: bytes) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=path.suffix)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _generate(functions: Sequence[ca.Function], folder: Path, stem: str, header: bool = False) -> Path:
    cg = ca.CodeGenerator(f"{stem}.c", {"with_header": header})
    for f in functions:
        cg.add(f)
    cg.generate(str(folder) + os.sep)
    return folder / f"{stem}.c"


def _own_library(lib: Path, digest: str) -> bool:
    """Whether ``lib`` is a regular file (not a symbolic link) owned by the current user
    whose SHA-256 is ``digest``."""
    try:
        fd = os.open(lib, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        return False
    with os.fdopen(fd, "rb") as fh:
        st = os.fstat(fh.fileno())
        uid = _uid()
        if not stat.S_ISREG(st.st_mode) or (uid is not None and st.st_uid != uid):
            return False
        h = hashlib.sha256()
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest() == digest


def _valid_entry(folder: Path, key: str) -> Path | None:
    """The library of a cache entry if its record is readable and names the library the
    key allows (``<key>-<digest16>.so`` in ``folder``, the record's digest's prefix), a
    regular file of the current user's whose digest matches; else None."""
    try:
        if not re.fullmatch(r"[0-9a-f]{32}", key):
            return None
        meta = json.loads((folder / f"{key}.json").read_text())
        digest, name = meta["sha256"], meta["library"]
        if (meta.get("key") != key or not isinstance(digest, str) or not isinstance(name, str)
                or not re.fullmatch(r"[0-9a-f]{64}", digest) or name != f"{key}-{digest[:16]}.so"):
            return None
        lib = folder / name
        return lib if _own_library(lib, digest) else None
    except (OSError, ValueError, KeyError, TypeError):
        return None


_lock = threading.Lock()
#: every library loaded in this process: key -> {name: Function}
_loaded: dict = {}
#: what the last compile_functions call did (for studies and tests)
last_build: dict = {}
#: compile_functions calls in this process by what they did: "memory" (already loaded),
#: "cache" (loaded from the build cache), "compiled" (built now), "vm" (not in the cache
#: within :func:`cached_only`: the virtual machine's Functions), "background" (its build
#: started or under way, the virtual machine's Functions meanwhile); a sweep reports each
#: case's share (:mod:`symcable.sweep`)
build_counts: dict = {"memory": 0, "cache": 0, "compiled": 0, "vm": 0, "background": 0}
_cached_only = threading.local()


@contextmanager
def cached_only():
    """Within this block (in this thread), :func:`compile_functions` loads what is already
    loaded or in the build cache but compiles nothing: for Functions not there it returns
    them as they are (the virtual machine's; same results, slower). A sweep's workers run
    so (:mod:`symcable.sweep`): what the client compiled for the first case they load from
    the cache; a case of another model structure runs in the virtual machine rather than
    compile on a worker."""
    before = getattr(_cached_only, "on", False)
    _cached_only.on = True
    try:
        yield
    finally:
        _cached_only.on = before


def compile_functions(functions: Sequence[ca.Function], *, jacobians: bool = False,
                      what: str = "generated C", wait: bool = True) -> dict:
    """Compile CasADi Functions to one shared library (through the cache) and load them.

    Parameters
    ----------
    functions : sequence of casadi.Function
        Functions with distinct names; SX or MX (MX graphs may call other Functions and
        code-generatable linear solvers such as ``"qr"``).
    jacobians : bool
        Also generate each Function's Jacobian (``jac_<name>``), so a loaded Function can
        be differentiated (as IPOPT and CasADi's rootfinder need).
    what : str
        What is compiled, for the one-line notice shown while compiling
        (``compiling <what> for this model (once, cached) …``, see
        :func:`symcable.progress.notice`); nothing is shown when the cache has it.
    wait : bool
        False: when the cache does not have them, start their build in the background
        (:mod:`.background_build`) and return ``functions`` as given (the virtual machine's)
        meanwhile; ``last_build["action"]`` is then ``"background"``.

    Returns
    -------
    dict
        ``{name: casadi.Function}`` loaded from the library with ``casadi.external``
        (within :func:`cached_only`, when the cache does not have them, and when the cache
        folder is not fit to use (one :class:`CodegenWarning`, see the module's *Trust*):
        ``functions`` as given).

    Raises
    ------
    SymcableError
        No compiler, or the compiler failed (the message has its last lines).
    """
    cc = compiler()
    if cc is None:
        raise SymcableError("generated C needs a C compiler: set CC or install cc/gcc/clang "
                            "(or pass codegen=False)")
    funcs = list(functions)
    if jacobians:
        funcs = funcs + [f.jacobian() for f in funcs]
    size = graph_estimate(funcs)
    if size > MAX_COMPILE_SIZE:
        last_build.update(key=None, action="vm", seconds=0.0)
        build_counts["vm"] += 1
        warnings.warn(f"{what}: about {size / 1e6:.0f} million characters of C "
                      f"(MAX_COMPILE_SIZE: {MAX_COMPILE_SIZE / 1e6:.0f} million), which the C "
                      "compiler would need many GB and minutes to compile; running it in the "
                      "CasADi virtual machine instead (same results, slower)", CodegenWarning,
                      stacklevel=3)
        return {f.name(): f for f in functions}
    key, flags = _key(funcs, cc)
    with _lock:
        if key in _loaded:
            last_build.update(key=key, action="memory", seconds=0.0)
            build_counts["memory"] += 1
            return _loaded[key]
        folder = _trusted_folder(stacklevel=4)
        if folder is None:
            last_build.update(key=key, action="vm", seconds=0.0)
            build_counts["vm"] += 1
            return {f.name(): f for f in functions}
        t0 = time.perf_counter()
        lib = _valid_entry(folder, key)
        action = "cache"
        if lib is None and getattr(_cached_only, "on", False):
            last_build.update(key=key, action="vm", seconds=0.0)
            build_counts["vm"] += 1
            return {f.name(): f for f in functions}
        if lib is None and not wait:
            if background_build.start(key, _background_args(funcs, folder, key, cc, flags)):
                notice(f"compiling {what} for this model in the background (once, cached); "
                       "this run uses the CasADi virtual machine …")
            last_build.update(key=key, action="background", seconds=time.perf_counter() - t0)
            build_counts["background"] += 1
            return {f.name(): f for f in functions}
        if lib is None:
            notice(f"compiling {what} for this model (once, cached) …")
            lib = _build(funcs, folder, key, cc, flags)
            action = "compiled"
        loaded = {f.name(): ca.external(f.name(), str(lib)) for f in functions}
        _loaded[key] = loaded
        last_build.update(key=key, action=action, seconds=time.perf_counter() - t0,
                          library=str(lib), flags=list(flags))
        build_counts[action] += 1
        return loaded


def _build(funcs, folder: Path, key: str, cc: str, flags: tuple = FLAGS) -> Path:
    with tempfile.TemporaryDirectory(dir=folder, prefix=".build-") as tmp:
        tmp = Path(tmp)
        src = _generate(funcs, tmp, f"sc_{key[:16]}")
        out = tmp / "lib.so"
        cmd = [cc, *flags, str(src), "-o", str(out), "-lm"]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0 or not out.exists():
            tail = " | ".join((proc.stderr or proc.stdout).strip().splitlines()[-3:])
            raise SymcableError(f"the C compiler failed on generated code ({' '.join(cmd[:2])} "
                                f"...): {tail or f'no output, exit status {proc.returncode}'}")
        return store_library(out, folder, key, cc, flags, [f.name() for f in funcs])


def _background_args(funcs, folder: Path, key: str, cc: str, flags: tuple) -> list:
    """Write the C of ``funcs`` into a new build folder; the args of :func:`_build_job`."""
    build = Path(tempfile.mkdtemp(dir=folder, prefix=".build-"))
    return [folder, key, _generate(funcs, build, f"sc_{key[:16]}"), cc, *flags]


def _build_job(folder: str, key: str, src: str, cc: str, *flags: str) -> int:
    """A background build (:mod:`.background_build`): ``src`` compiled into the entry ``key``
    (0 when stored), its build folder removed."""
    build = Path(src).parent
    try:
        out = build / "lib.so"
        proc = subprocess.run([cc, *flags, src, "-o", str(out), "-lm"], capture_output=True)
        ok = proc.returncode == 0 and out.exists()
        return 0 if ok and store_library(out, Path(folder), key, cc, flags, []) else 1
    finally:
        shutil.rmtree(build, ignore_errors=True)


def store_library(out: Path, folder: Path, key: str, cc: str, flags: tuple, names: list) -> Path:
    """Move the built library ``out`` into the cache ``folder`` as the entry ``key`` (its
    digest recorded, written atomically); its path."""
    digest = _digest(out)
    lib = folder / f"{key}-{digest[:16]}.so"
    if not _own_library(lib, digest):
        os.replace(out, lib)  # replaces a symbolic link itself, never its target
    meta = {"key": key, "library": lib.name, "sha256": digest, "casadi": ca.__version__,
            "compiler": cc, "flags": list(flags), "functions": names,
            "created": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    _write_atomic(folder / f"{key}.json", json.dumps(meta, indent=1).encode())
    return lib


# --------------------------------------------------------------------------- the cache

def _own_entries(folder: Path) -> list:
    """The cache's own files and build folders in ``folder`` (see the module's *Trust*):
    [(path, kind)], kind "record", "library", "temp" or "build"."""
    if not folder.is_dir():
        return []
    found = []
    for p in folder.iterdir():
        name = p.name
        kind = ("record" if _RECORD.fullmatch(name) else "library" if _LIBRARY.fullmatch(name)
                else "temp" if _TEMP.fullmatch(name) else "build" if _BUILD.fullmatch(name) else None)
        if kind is not None:
            found.append((p, kind))
    return found


def cache_info() -> dict:
    """``{"folder": str, "entries": int, "bytes": int}`` of the build cache: its records
    and the bytes of its own files (records, libraries, temporary files)."""
    folder = cache_dir()
    entries, size = 0, 0
    for p, kind in _own_entries(folder):
        entries += kind == "record"
        try:
            st = p.lstat()
        except OSError:
            continue
        if stat.S_ISREG(st.st_mode) and kind != "build":
            size += st.st_size
    return {"folder": str(folder), "entries": entries, "bytes": size}


def clear_cache() -> int:
    """Delete the build cache's own entries (records, libraries, temporary files and build
    folders, see the module's *Trust*; nothing else in the folder); returns the number of
    records removed. Libraries already loaded in running processes stay usable (POSIX
    unlink)."""
    n = 0
    for p, kind in _own_entries(cache_dir()):
        try:
            st = p.lstat()
            if kind == "build" and stat.S_ISDIR(st.st_mode):
                shutil.rmtree(p, ignore_errors=True)
            elif kind != "build" and not stat.S_ISDIR(st.st_mode):
                p.unlink()
                n += kind == "record"
        except OSError:
            continue
    with _lock:
        _loaded.clear()
    return n


# --------------------------------------------------------------------------- export

def export_sources(functions: Sequence[ca.Function], folder, stem: str) -> tuple[Path, Path]:
    """Write standalone C sources ``<stem>.c`` and header ``<stem>.h`` for ``functions``
    into ``folder`` (created if needed); returns their paths. No compiler needed."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    src = _generate(functions, folder, stem, header=True)
    return src, folder / f"{stem}.h"


if __name__ == "__main__" and sys.argv[1:2] == ["--build"]:
    sys.exit(_build_job(*sys.argv[2:]))
