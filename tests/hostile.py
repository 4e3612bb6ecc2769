"""The hostile-input corpus: scene files, MoorDyn decks, motion tables, sweep files and
command lines that a careless or malicious user may hand to ``symcable``, each with what
must happen: ``"refused"`` (exit status 2, one line on stderr naming the problem),
``"usage"`` (argparse refuses the command line: exit status 2, its usage and one error line),
or ``"ok"`` (exit status 0: odd but valid input runs). Nothing may print a traceback or hang.

:func:`build` writes the files into a folder and returns the cases; ``hostile_runner.py``
runs them in one process (so that its peak memory bounds every case's).
"""
from __future__ import annotations

import json
import os
from pathlib import Path

#: a small planar line with a harmonic fairlead motion (every planar analysis runs on it)
PLANAR = '''name = {name}
[environment]
depth = 100.0
[line_types.{type_key}]
EA = 1e9
mass = 100.0
diameter = 0.1
[[sections]]
type = {type_name}
length = 150.0
segments = {segments}
[end_a]
position = [-120.0, -100.0]
condition = "pinned"
[end_b]
position = [0.0, -10.0]
condition = "pinned"
[end_b.motion]
kind = "harmonic"
period = {period}
amplitude = [{amplitude}, 0.5]
'''

#: a small 3D line from a moving vessel point to a free buoy-weight point
SYSTEM = '''name = "system"
model = "cable3d"
[environment]
water_density = 1025.0
[line_types.wire]
EA = 1.0e5
mass = 0.02
diameter = 0.002
damping = 100.0
[points.{free}]
kind = "free"
position = [0.0, 0.0, -12.0]
mass = 10.0
volume = 0.004
diameter = 0.2
cd = 0.5
ca = 0.2
[points.{top}]
kind = "vessel"
position = [0.0, 0.0, -1.0]
[points.{top}.motion]
kind = {motion_kind}
{motion}
[[lines]]
name = {line}
end_a = {free_ref}
end_b = {top_ref}
[[lines.sections]]
type = "wire"
length = 10.0
segments = {segments}
'''

DECK = '''MoorDyn v2 input file
---------------------- LINE TYPES -----------------------------------------------------
TypeName   Diam    Mass/m     EA     BA/-zeta    EI    Cd     Ca    CdAx   CaAx
(name)     (m)     (kg/m)     (N)    (N-s/-)   (N-m^2)  (-)  (-)    (-)    (-)
chain      0.1     100.0      1e9    -0.8       0      1.2    1.0    0.2    0.0
---------------------- POINTS --------------------------------
ID   Attachment  X       Y     Z      Mass   Volume  CdA    CA
(#)  (-)         (m)     (m)   (m)    (kg)   (mˆ3)   (m^2)  (-)
1    Fixed       -120.0  0.0   -100.0  0     0       0      0
2    Fixed       0.0     0.0   -10.0   0     0       0      0
---------------------- LINES --------------------------------------
ID   LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)    (#)      (#)      (m)       (-)      (-)
1    chain     1        2        150.0     {segments}   -
---------------------- OPTIONS -----------------------------------------
0.001    dtM
100.0    WtrDpth
--------------------- need this line ------------------
'''

SWEEP = '''scene = {scene}
analysis = "static"
{extra}
'''


def _q(text: str) -> str:
    """A TOML basic string of ``text`` (JSON's escapes are TOML's)."""
    return json.dumps(text, ensure_ascii=False)


def planar(name="base", type_name="ch", segments=10, period="10.0", amplitude="1.0",
           type_key=None) -> str:
    return PLANAR.format(name=_q(name), type_key=type_key or _q(type_name),
                         type_name=_q(type_name), segments=segments, period=period,
                         amplitude=amplitude)


def system(line="cable", free="weight", top="top", segments=4,
           motion='period = 2.0\namplitude = [0.0, 0.0, 0.05]', motion_kind='"harmonic"',
           free_ref=None, top_ref=None) -> str:
    return SYSTEM.format(line=_q(line), free=_q(free), top=_q(top), segments=segments,
                         motion=motion, motion_kind=motion_kind,
                         free_ref=_q(free if free_ref is None else free_ref),
                         top_ref=_q(top if top_ref is None else top_ref))


def build(folder: Path) -> list:
    """Write the corpus into ``folder``; returns ``[{"id", "argv", "expect"}]`` (argv
    relative to ``folder``, where the runner runs them)."""
    folder = Path(folder)
    cases = []

    def write(name: str, text: str | bytes) -> str:
        p = folder / name
        p.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
        return name

    def case(cid: str, expect: str, *argv: str) -> None:
        cases.append({"id": cid, "argv": list(argv), "expect": expect})

    write("base.toml", planar())

    # ---- names: odd names that are valid run; names the rule refuses are one line
    for i, name in enumerate(["my-cable", "a__b", "_x", "x_", "1", "null", "jac", "hess",
                              "a-_-b", "9" * 64]):
        f = write(f"line_name{i}.toml", system(line=name))
        case(f"line name {name!r}: check", "ok", "check", f)
        case(f"line name {name!r}: static", "ok", "static", f)
    for i, name in enumerate(["p-1", "__", "_", "0"]):
        f = write(f"point_name{i}.toml", system(free=name, top=f"{name}top"))
        case(f"point names {name!r}: simulate", "ok", "simulate", f, "--duration", "0.2",
             "--dt", "0.05")
    for i, name in enumerate(["Ωcable", "a b", "a.b", "a@b", "", "x" * 65, "x\n", "a/b",
                              "$x$", "a*/b", "é"]):
        f = write(f"bad_line_name{i}.toml", system(line=name))
        case(f"line name {name!r} refused", "refused", "check", f)
    for i, name in enumerate(['*/ int x = system("touch PWNED"); /*', "$x^2$ \\alpha",
                              'quote " and \\ backslash', "Ω ünïcode 🌊", "?" * 3 + "/"]):
        f = write(f"scene_name{i}.toml", planar(name=name))
        case(f"scene name {name!r}: static with plot", "ok", "static", f, "--plot",
             f"scene_name{i}.png")
    for i, name in enumerate(["tab\there", "new\nline", "x" * 201, "nul\x00"]):
        f = write(f"bad_scene_name{i}.toml", planar(name=name))
        case(f"scene name {name!r} refused", "refused", "check", f)
    f = write("type_dollar.toml", planar(type_name="$ch$ {x}"))
    case("line type name with $: static with plot", "ok", "static", f, "--plot", "type.png")
    f = write("type_newline.toml", planar(type_name="a\nb"))
    case("line type name with a newline refused", "refused", "check", f)

    # ---- sizes
    for segs in (10**7, 10**5, 20_001, 10**400):
        f = write(f"segments{len(str(segs))}.toml", planar(segments=segs))
        case(f"segments = 1e{len(str(segs)) - 1}", "refused", "check", f)
    f = write("segments_ok_with_option.toml", planar(segments=30))
    case("segments over a lowered limit", "refused", "check", f, "--max-segments", "20")
    many = planar(segments=1).split("[[sections]]")
    body = "[[sections]]" + many[1].split("[end_a]")[0]
    f = write("many_sections.toml", many[0] + body * 30_000 + "[end_a]" +
              many[1].split("[end_a]")[1])
    case("30,000 sections of one segment", "refused", "check", f)
    two = system(segments=15_000).replace("[[lines]]", "[[lines]]\nname = \"other\"\nend_a = "
                                          "\"weight\"\nend_b = \"top\"\n[[lines.sections]]\n"
                                          "type = \"wire\"\nlength = 10.0\nsegments = 15000\n"
                                          "[[lines]]", 1)
    f = write("two_lines_over.toml", two)
    case("two lines of 15,000 segments each", "refused", "check", f)
    rod = (Path(__file__).resolve().parents[1] / "symcable" / "data" / "seed000_rod.toml")
    f = write("rod_segments.toml", rod.read_text().replace("segments = 400 ", "segments = 4000 "))
    case("a rod of 4,000 segments", "refused", "check", f)
    f = write("rod_ok_with_option.toml", rod.read_text())
    case("a rod of 400 segments over a lowered rod limit", "refused", "check", f,
         "--max-rod-segments", "100")
    f = write("deck_numsegs.txt", DECK.format(segments=10**9))
    case("MoorDyn deck NumSegs = 1e9", "refused", "check", f)
    f = write("deck_ok.txt", DECK.format(segments=10))
    case("MoorDyn deck, 10 segments", "ok", "check", f)
    case("simulate --duration 1e12", "refused", "simulate", "base.toml", "--duration", "1e12")
    case("simulate --dt 1e-9", "refused", "simulate", "base.toml", "--dt", "1e-9")
    case("simulate over a lowered step limit", "refused", "simulate", "base.toml",
         "--max-steps", "50")
    case("3D simulate --duration 1e12", "refused", "simulate", "line_name0.toml",
         "--duration", "1e12")
    case("modes --n 1e9", "ok", "modes", "base.toml", "--n", "1000000000")
    grid = "[grid]\n" + "\n".join(f'"end_b.position" = [{", ".join(f"[{x}.0, -10.0]" for x in range(2000))}]'
                                  .splitlines()) + '\n"environment.depth" = [' + \
        ", ".join(f"{100 + x / 1000:.4f}" for x in range(2000)) + "]\n"
    f = write("grid_big.toml", SWEEP.format(scene=_q("base.toml"), extra=grid))
    case("sweep grid of 2000 x 2000", "refused", "sweep", f, "--workers", "0", "--limit", "1")

    # ---- special files
    os.mkfifo(folder / "fifo.toml")
    os.mkfifo(folder / "fifo.txt")
    (folder / "a_folder.toml").mkdir()
    with open(folder / "sparse.toml", "wb") as fh:  # 20 MB that take no disk
        fh.truncate(20 << 20)
    with open(folder / "sparse_table.txt", "wb") as fh:
        fh.truncate(20 << 20)
    os.symlink("/dev/zero", folder / "zero_link.toml")
    for path in ("/dev/zero", "/dev/urandom", "/dev/null", "fifo.toml", "a_folder.toml",
                 "sparse.toml", "zero_link.toml", "missing.toml"):
        case(f"scene file {path}", "refused", "check", path)
    write("binary.toml", bytes(range(256)) * 40)
    case("binary scene file", "refused", "check", "binary.toml")
    write("latin1.toml", "name = \"caf\xe9\"\n".encode("latin-1"))
    case("scene file not UTF-8", "refused", "check", "latin1.toml")
    write("empty.toml", "")
    case("empty scene file", "refused", "check", "empty.toml")
    for i, table in enumerate(("/dev/zero", "fifo.txt", "a_folder.toml", "sparse_table.txt",
                               "/dev/null", "binary.toml", "missing.txt")):
        f = write(f"table{i}.toml", system(motion=f"file = {_q(table)}",
                                           motion_kind='"table"'))
        case(f"motion table {table}", "refused", "check", f)
    write("sweep_scene_fifo.toml", SWEEP.format(scene=_q("fifo.toml"),
                                                extra='[[cases]]\nname = "a"\n"end_b.position" = [0.0, -10.0]'))
    case("sweep whose scene is a FIFO", "refused", "sweep", "sweep_scene_fifo.toml",
         "--workers", "0")
    case("sweep file a FIFO", "refused", "sweep", "fifo.toml", "--workers", "0")
    case("sweep file /dev/zero", "refused", "sweep", "/dev/zero", "--workers", "0")
    case("codegen into /dev/null", "refused", "codegen", "base.toml", "--out", "/dev/null")
    case("--save into a missing folder", "refused", "static", "base.toml", "--save",
         "missing/x.npz")
    case("--plot of an unknown format", "refused", "static", "base.toml", "--plot", "x.xyz")
    case("--save of an unknown format", "refused", "static", "base.toml", "--save", "x.xyz")

    # ---- nesting
    for depth in (40, 1000, 100_000):
        f = write(f"nested_array{depth}.toml", planar() + "x = " + "[" * depth + "1" +
                  "]" * depth + "\n")
        case(f"array nested {depth} deep", "refused", "check", f)
    f = write("nested_inline.toml", planar() + "x = " + "{a = " * 200 + "1" + "}" * 200 + "\n")
    case("inline tables nested 200 deep", "refused", "check", f)
    f = write("nested_dotted.toml", "x." + ".".join(["a"] * 5000) + " = 1\n" + planar())
    case("dotted key 5000 deep", "refused", "check", f)
    f = write("nested_sweep.toml", SWEEP.format(scene=_q("base.toml"), extra="[[cases]]\n"
              'name = "a"\n"end_b.position" = ' + "[" * 5000 + "]" * 5000))
    case("sweep case nested 5000 deep", "refused", "sweep", f, "--workers", "0")

    # ---- bad numbers in the scene
    for cid, old, new in [
            ("segments = 1.5", "segments = 10", "segments = 1.5"),
            ("segments = true", "segments = 10", "segments = true"),
            ("segments = -1", "segments = 10", "segments = -1"),
            ("length = 1e400", "length = 150.0", "length = 1e400"),
            ("length = nan", "length = 150.0", "length = nan"),
            ("length = -inf", "length = 150.0", "length = -inf"),
            ("EA = 0", "EA = 1e9", "EA = 0"),
            ("EA = 1e308", "EA = 1e9", "EA = 1e308"),
            ("mass = 1e308", "mass = 100.0", "mass = 1e308"),
            ("diameter = 1e300", "diameter = 0.1", "diameter = 1e300"),
            ("diameter = 0", "diameter = 0.1", "diameter = 0.0"),
            ("depth = 1e-300", "depth = 100.0", "depth = 1e-300"),
            ("position 1e308", "position = [0.0, -10.0]", "position = [1e308, -10.0]"),
            ("position nan", "position = [0.0, -10.0]", "position = [nan, -10.0]"),
            ("position of 3 numbers", "position = [0.0, -10.0]", "position = [0.0, 0.0, -10.0]"),
            ("position a string", "position = [0.0, -10.0]", 'position = "here"'),
            ("amplitude 1e300", "amplitude = [1.0", "amplitude = [1e300"),
            ("gravity 0", "depth = 100.0", "depth = 100.0\ngravity = 0.0"),
            ("water density -1", "depth = 100.0", "depth = 100.0\nwater_density = -1.0"),
            ("huge integer EA", "EA = 1e9", "EA = " + "9" * 400),
            ("unknown key", "depth = 100.0", "depth = 100.0\ndepht = 1.0")]:
        f = write(f"num_{len(cases)}.toml", planar().replace(old, new, 1))
        case(f"scene {cid}", "refused", "static", f)
    f = write("period_tiny.toml", planar(period="1e-300"))
    case("motion period 1e-300: simulate", "refused", "simulate", f)
    f = write("gravity_huge.toml", planar().replace("depth = 100.0", "depth = 100.0\n"
                                                    "gravity = 1e30"))
    case("gravity 1e30: static", "refused", "static", f)

    # ---- bad numbers on the command line
    for opt, val in (("--dt", "0"), ("--dt", "-1"), ("--dt", "nan"), ("--dt", "inf"),
                     ("--duration", "0"), ("--duration", "-1"), ("--duration", "nan"),
                     ("--duration", "inf")):
        case(f"simulate {opt} {val}", "refused", "simulate", "base.toml", opt, val)
    case("simulate --duration 1e-300", "ok", "simulate", "base.toml", "--duration",
         "1e-300")
    for opt, val in (("--dt", "abc"), ("--max-segments", "0"), ("--max-segments", "-5"),
                     ("--max-steps", "inf"), ("--max-file-mb", "nan")):
        case(f"simulate {opt} {val}", "usage", "simulate", "base.toml", opt, val)
    case("offsets --n 1e9", "refused", "offsets", "towed_body", "--body", "fish", "--n",
         "1000000000")
    case("offsets --range nan 1", "refused", "offsets", "towed_body", "--body", "fish",
         "--range", "nan", "1")
    case("offsets --n 0", "refused", "offsets", "towed_body", "--body", "fish", "--n", "0")
    case("modes --n 0", "refused", "modes", "base.toml", "--n", "0")
    case("modes --n -1", "refused", "modes", "base.toml", "--n", "-1")
    case("sweep --workers 100000", "refused", "sweep", "grid_small.toml", "--workers",
         "100000")
    write("grid_small.toml", SWEEP.format(scene=_q("base.toml"), extra='[grid]\n'
                                          '"end_b.position" = [[0.0, -10.0], [1.0, -10.0]]'))
    return cases
