#!/usr/bin/env python3
"""Mutation test of the apps' readers (issue 14): bad input never crashes, hangs or silently
misbehaves; it gives one clear error line naming the file (or key) and exit status 1.

It makes small valid inputs of every kind the apps read (a 6-frame pf2_synth sequence with its
lists, PNGs, camera.txt and gt/boxes.txt; trajectories; a config file; tiny ASCII and binary PLY
maps; a run folder's humans.txt and humans.json; the shipped body model .npz; a pose file; a boxes
file), derives mutants from them deterministically (bit flips, truncation at several points,
garbage bytes, an empty file, a duplicated line, a number replaced by nan/inf/1e308/-1/huge, a
10 MB line, a folder in place of the file, a missing file, and a few structured ones per format),
runs the app that reads each one under a timeout and an address-space limit, and classifies it:

  ok       exit 0
  clean    exit 1, exactly one non-empty stderr line, shorter than 500 characters, without
           control characters, naming the mutated file (or the key / option of a named case)
  unnamed  like clean, but the line names neither the file nor the key
  messy    exit 1 with several lines, a huge line or control characters in it
  crash    killed by a signal, exit status > 1, or 'terminate called' on stderr
  hang     still running at the timeout (killed)
  slow     a named case that must fail fast took longer than its limit
  silent   exit 0 for an input that is invalid for certain (MUST_REFUSE: e.g. a PNG with a CRC
           error, a PLY face index past the vertex count, a line given twice), or a named case
           that accepted what it must refuse, printed a wrong result or left what it must not

Besides the mutants, the 'issue' kind runs the cases issue 14 lists by name (each must be refused
with a line naming its key or file) and a few found while writing this test. Prints a table of counts per kind and outcome and every case
that is not ok or clean with the command that reproduces it. Exit status 1 when any case is
unnamed, messy, crash, hang, slow or silent; 77 (skip) when the apps are missing.

Usage: mutation_test.py --slam P --eval P --synth P --detect P --body P [--view P] --repo DIR
       --work DIR [--per-kind 12] [--timeout 60] [--jobs 2] [--seed 14] [--kinds a,b]
Python 3 standard library only. The pf2_view cases need --view and xvfb-run (skipped without).
PF2_MUTATION_VERBOSE=1 also lists every case with its outcome and error line.
"""
import argparse
import os
import random
import re
import shlex
import shutil
import signal
import struct
import subprocess
import sys
import threading
import time
import zipfile
import zlib
from concurrent.futures import ThreadPoolExecutor

FAILING = ("unnamed", "messy", "crash", "hang", "slow", "silent")
OUTCOMES = ("ok", "clean") + FAILING
MAX_LINE = 500
MEMORY_LIMIT_KB = 2_000_000  # address space of every app run: a reader that tries to take GBs fails
LONG_LINE = 10 * 1024 * 1024

# Mutants that make the input invalid for certain, by operator: these must be refused (exit 0 is
# 'silent'). Others (a bit flip in a comment, a truncation at a line end) may leave a valid file.
# A duplicated line is refused like camera.txt's 'fx twice' and a trajectory's repeated stamp.
MUST_REFUSE = {
    "lists": {"empty", "missing", "folder", "10MB-line", "duplicated-line", "number-nan", "number-inf",
              "same-stamp-two-files", "unknown-image"},
    "png": "all",
    "ply": {"empty", "folder", "vertex-count-1e9", "face-index-out-of-range", "face-index-negative",
            "truncated-body", "vertex-count-negative", "face-of-200-vertices", "no-end_header",
            "unknown-property-type", "garbage-after-header"},
    # Not the flips of the first local header (libzip, like Python's zipfile, reads the central
    # directory) nor a model without shape coefficients (valid, if useless).
    "npz": {"empty", "missing", "folder", "truncated-half", "deflate-data-bit-flips", "garbage",
            "truncated-at-100-bytes", "member-f.npy-removed", "v_template-shape-1e9", "v_template-shape-13380x2",
            "f-index-out-of-range", "kintree-parent-out-of-range", "kintree-parent-cycle", "weights-nan",
            "J_regressor-complex-dtype", "v_template-payload-short"},
    "config": {"missing", "folder", "10MB-line", "duplicated-line", "number-nan", "number-inf",
               "key-without-value", "binary-zero-bytes"},
    "camera": {"empty", "folder", "10MB-line", "duplicated-line", "number-nan", "number-inf", "number-1e308",
               "fx-twice", "unknown-key", "width-0", "cx-5000"},
    "trajectory": {"empty", "missing", "folder", "10MB-line", "duplicated-line", "number-nan", "number-inf",
                   "zero-quaternion", "all-stamps-equal"},
    "humans": {"10MB-line", "number-nan", "pose-of-71-numbers", "nested-200000-deep", "folder", "NaN-literal",
               "id-string", "duplicated-line", "truncated-half"},
    "pose": {"missing", "folder", "10MB-line", "duplicated-line", "number-nan", "number-inf", "unknown-joint",
             "three-numbers-missing"},
    "boxes": {"missing", "folder", "10MB-line", "number-nan", "number-inf", "corner-1e308"},
}

DIR = "<dir>"          # replacement: a folder where the file was
MISSING = "<missing>"  # replacement: the file removed


class Case:
    """One run: what was mutated, the command, the names its error line may give, expectations."""

    def __init__(self, kind, name, argv, names, expect_error=False, max_seconds=None, check=None,
                 view=False, cwd=None):
        self.kind, self.name, self.argv, self.names = kind, name, argv, names
        self.expect_error, self.max_seconds, self.check, self.view = expect_error, max_seconds, check, view
        self.cwd = cwd
        self.outcome, self.detail, self.seconds, self.code = None, "", 0.0, None


# ---------------------------------------------------------------------------------------------
# Mutation operators: bytes in, bytes out, deterministic for a given random.Random.

NUMBER = re.compile(rb"(?<![A-Za-z_0-9.])-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![A-Za-z_0-9])")


def data_lines(data):
    """Indices of the lines that hold data (not blank, not '#' comments)."""
    lines = data.split(b"\n")
    return lines, [i for i, l in enumerate(lines) if l.strip() and not l.lstrip().startswith(b"#")]


def flip_bits(data, rng, count, lo=0, hi=None):
    b = bytearray(data)
    hi = len(b) if hi is None else min(hi, len(b))
    for _ in range(count):
        i = rng.randrange(lo, hi)
        b[i] ^= 1 << rng.randrange(8)
    return bytes(b)


def truncate(data, fraction):
    return data[: int(len(data) * fraction)]


def garble(data, rng, length):
    """Overwrite a random stretch with random bytes."""
    b = bytearray(data)
    start = rng.randrange(max(1, len(b) - length))
    b[start:start + length] = bytes(rng.randrange(256) for _ in range(length))
    return bytes(b)


def duplicate_line(data, rng):
    lines, idx = data_lines(data)
    i = rng.choice(idx)
    lines.insert(i + 1, lines[i])
    return b"\n".join(lines)


def replace_number(data, rng, value, line_pick=None):
    """Replace one number of a data line (a random one, or on the line_pick-th data line)."""
    lines, idx = data_lines(data)
    candidates = [i for i in idx if NUMBER.search(lines[i])]
    i = candidates[line_pick % len(candidates)] if line_pick is not None else rng.choice(candidates)
    matches = list(NUMBER.finditer(lines[i]))
    m = rng.choice(matches)
    lines[i] = lines[i][:m.start()] + value + lines[i][m.end():]
    return b"\n".join(lines)


def long_line(data, rng):
    """A 10 MB line of letters, digits and spaces after the first data line."""
    lines, idx = data_lines(data)
    r = random.Random(rng.random())
    alphabet = b"abcdefghijklmnopqrstuvwxyz0123456789 "
    chunk = bytes(r.choice(alphabet) for _ in range(4096))
    garbage = (chunk * (LONG_LINE // len(chunk) + 1))[:LONG_LINE]
    lines.insert(idx[0] + 1 if idx else 0, garbage)
    return b"\n".join(lines)


def text_mutants(data, rng):
    """The standard mutants of a text format, (name, bytes or DIR/MISSING): the first REQUIRED
    ones are always run (every operator of the issue), the others are drawn from."""
    return [
        ("empty", b""),
        ("missing", MISSING),
        ("folder", DIR),
        ("10MB-line", long_line(data, rng)),
        ("truncated-half", truncate(data, 0.5)),
        ("bit-flips", flip_bits(data, rng, 3)),
        ("garbage-bytes", garble(data, rng, 24)),
        ("duplicated-line", duplicate_line(data, rng)),
        ("number-nan", replace_number(data, rng, b"nan")),
        # drawn from:
        ("truncated-mid-line", truncate(data, 0.77)),
        ("number-1e308", replace_number(data, rng, b"1e308")),
        ("number--1", replace_number(data, rng, b"-1")),
        ("number-inf", replace_number(data, rng, b"inf")),
        ("number-huge-integer", replace_number(data, rng, b"99999999999999999999999")),
    ]


REQUIRED = 9


# ---------------------------------------------------------------------------------------------
# Small valid inputs.

def png_bytes(width, height, bit_depth, colour_type, pixel=0, idat=None):
    """A PNG (stdlib encoder): every pixel's samples equal to `pixel`; or raw `idat` bytes."""
    channels = {0: 1, 2: 3, 6: 4}[colour_type]
    sample = bit_depth // 8
    if idat is None:
        row = b"\x00" + (pixel.to_bytes(sample, "big") * channels) * width
        idat = zlib.compress(row * height, 6)

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


TINY_PLY_ASCII = b"""ply
format ascii 1.0
comment mutation test: a 2 m x 2 m floor and a wall
element vertex 6
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
element face 4
property list uchar int vertex_indices
end_header
-1 -1 0 200 30 30
1 -1 0 200 30 30
1 1 0 200 30 30
-1 1 0 200 30 30
-1 1 1 30 200 30
1 1 1 30 200 30
3 0 1 2
3 0 2 3
3 3 2 5
3 3 5 4
"""


def tiny_ply_binary(vertex_count=None, faces=None):
    vertices = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0), (-1, 1, 1), (1, 1, 1)]
    faces = faces if faces is not None else [(0, 1, 2), (0, 2, 3), (3, 2, 5), (3, 5, 4)]
    header = ("ply\nformat binary_little_endian 1.0\ncomment mutation test\n"
              "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\n"
              "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
              % (len(vertices) if vertex_count is None else vertex_count, len(faces))).encode()
    body = b"".join(struct.pack("<fffBBB", x, y, z, 90, 90, 200) for x, y, z in vertices)
    body += b"".join(struct.pack("<Biii", 3, *f) for f in faces)
    return header + body


POSE_FILE = b"""# joint rotations for pf2_body mesh --pose-file: NAME ax ay az (axis-angle, radians)
left_knee 0.6 0 0
right_knee 0.1 0 0
left_shoulder 0 0 -1.2
right_shoulder 0 0 1.2
left_elbow 0 -0.3 0
"""

SLAM_CONFIG = b"""# pf2_slam settings for the mutation test
run.max_frames 6
map.voxel_size 0.03
map.truncation 0.1
map.fuse_every 5
tracker.pyramid_levels 3
humans.min_frames 1
humans.gate 1.5
"""


# ---------------------------------------------------------------------------------------------
# npz/npy helpers (the body model).

def npy_split(data):
    """(header text, payload) of an .npy member (format 1.0/2.0)."""
    major = data[6]
    if major == 1:
        n = struct.unpack("<H", data[8:10])[0]
        return data[10:10 + n].decode("latin1"), data[10 + n:]
    n = struct.unpack("<I", data[8:12])[0]
    return data[12:12 + n].decode("latin1"), data[12 + n:]


def npy_join(header, payload):
    header = header.rstrip()
    pad = 64 - (10 + len(header) + 1) % 64
    text = (header + " " * (pad % 64) + "\n").encode("latin1")
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(text)) + text + payload


def write_npz(path, members):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=1) as z:
        for name, data in members.items():
            z.writestr(name, data)


# ---------------------------------------------------------------------------------------------

class Test:
    def __init__(self, args):
        self.a = args
        self.work = os.path.abspath(args.work)
        self.base = os.path.join(self.work, "base")
        self.cases = []
        self.view_lock = threading.Lock()
        self.xvfb = shutil.which("xvfb-run") if args.view else None
        self.skipped = []

    # -- files ----------------------------------------------------------------------------------
    def place(self, path, content):
        """Write `content` at path (bytes, DIR or MISSING), creating parents."""
        os.makedirs(os.path.dirname(path), exist_ok=True)
        if os.path.lexists(path):
            if os.path.isdir(path) and not os.path.islink(path):
                shutil.rmtree(path)
            else:
                os.remove(path)
        if content is DIR:
            os.makedirs(os.path.join(path, "inside"))
        elif content is not MISSING:
            with open(path, "wb") as f:
                f.write(content)

    def mirror(self, src, dst, replace):
        """dst mirrors folder src with symlinks to its files; replace = {relative path: content}."""
        for root, dirs, files in os.walk(src):
            rel = os.path.relpath(root, src)
            os.makedirs(os.path.join(dst, rel), exist_ok=True)
            for f in files:
                r = os.path.normpath(os.path.join(rel, f))
                if r not in replace:
                    os.symlink(os.path.join(root, f), os.path.join(dst, r))
        for r, content in replace.items():
            self.place(os.path.join(dst, r), content)
        return dst

    def add_file_cases(self, kind, mutants, file_name, argv):
        """One case per sampled (name, content) mutant: the content written as file_name in the case's
        folder, the app run with argv(case folder, file path)."""
        for i, (name, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            path = os.path.join(d, file_name)
            self.place(path, content)
            self.add(kind, file_name + ":" + name, argv(d, path), [file_name])

    def case_dir(self, kind, index):
        d = os.path.join(self.work, kind, "%02d" % index)
        os.makedirs(d, exist_ok=True)
        return d

    # -- setup ----------------------------------------------------------------------------------
    def setup(self):
        a = self.a
        shutil.rmtree(self.work, ignore_errors=True)
        os.makedirs(self.base)
        seq = os.path.join(self.base, "seq")
        self.must_run([a.synth, seq, "--frames", "6", "--people", "1", "--quiet"])
        run = os.path.join(self.base, "run")
        self.must_run([a.slam, seq, "-o", run, "--frames", "6", "--detector", "gt", "--quiet",
                       "--set", "humans.min_frames=1", "--set", "map.voxel_size=0.03",
                       "--set", "map.truncation=0.1", "--set", "map.octomap=false"])
        self.seq, self.run_dir = seq, run
        # A run folder for pf2_view: the run's trajectory and people, a tiny map.
        self.view_base = os.path.join(self.base, "view")
        os.makedirs(self.view_base)
        for f in ("trajectory.txt", "humans.txt", "humans.json"):
            shutil.copy(os.path.join(run, f), self.view_base)
        with open(os.path.join(self.view_base, "map.ply"), "wb") as f:
            f.write(TINY_PLY_ASCII)
        # Files read by the other apps.
        self.write(os.path.join(self.base, "slam.cfg"), SLAM_CONFIG)
        self.write(os.path.join(self.base, "pose.txt"), POSE_FILE)
        self.must_run([a.detect, seq, os.path.join(self.base, "detect"), "--max-frames", "6"])
        self.boxes = os.path.join(self.base, "detect", "boxes.txt")
        self.model = os.path.join(a.repo, "modules", "body", "data", "pf2_default_body.npz")
        shutil.copy(self.model, os.path.join(self.base, "body.npz"))
        self.model = os.path.join(self.base, "body.npz")
        # The valid inputs pass: a failure here is the test's own, not a mutant's.
        for argv in (self.slam_argv(seq, os.path.join(self.base, "check_slam")),
                     [a.eval, os.path.join(seq, "groundtruth.txt"), os.path.join(run, "trajectory.txt"),
                      "--rpe", "--delta-frames", "1"],
                     [a.body, "mesh", os.path.join(self.base, "check.obj"), "--model", self.model,
                      "--pose-file", os.path.join(self.base, "pose.txt")],
                     [a.detect, seq, os.path.join(self.base, "check_detect"), "--detector", "file",
                      "--boxes", self.boxes, "--max-frames", "6"],
                     self.slam_argv(seq, os.path.join(self.base, "check_cfg")) +
                     ["--config", os.path.join(self.base, "slam.cfg")]):
            self.must_run(argv)
        if self.xvfb:
            self.must_run(self.view_argv(self.view_base, os.path.join(self.base, "check.png")))

    def write(self, path, data):
        with open(path, "wb") as f:
            f.write(data)

    def read(self, path):
        with open(path, "rb") as f:
            return f.read()

    def must_run(self, argv):
        p = subprocess.run(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           timeout=300)
        if p.returncode != 0:
            sys.stderr.write("setup failed: %s\n%s" % (" ".join(map(shlex.quote, argv)),
                                                        p.stderr.decode(errors="replace")[-2000:]))
            sys.exit(2)

    def slam_argv(self, seq, out):
        return [self.a.slam, seq, "-o", out, "--no-map", "--frames", "6", "--detector", "none", "--quiet"]

    def view_argv(self, folder, shot):
        return ["xvfb-run", "-a", self.a.view, folder, "--screenshot", shot, "--size", "128x96"]

    def add(self, kind, name, *args, **kwargs):
        case = Case(kind, name, *args, **kwargs)
        operator = name.split(" (")[0].split(":")[-1]
        refuse = MUST_REFUSE.get(kind, ())
        if refuse == "all" or operator in refuse:
            case.expect_error = True
        case.out_path = None
        self.cases.append(case)

    def add_view(self, kind, name, folder, d, names, **kw):
        if not self.xvfb:
            self.skipped.append("%s/%s" % (kind, name))
            return
        self.add(kind, name, self.view_argv(folder, os.path.join(d, "shot.png")), names, view=True, **kw)

    def rng(self, kind):
        return random.Random("%d:%s" % (self.a.seed, kind))

    def sample(self, kind, mutants, keep=REQUIRED):
        """At most --per-kind mutants: the first `keep` of the list (the required operators) and
        the rest drawn with the kind's seed, in list order. A mutant equal to its original would
        test nothing: each was checked by the kind (see changed())."""
        n = self.a.per_kind
        if len(mutants) <= n:
            return mutants
        keep = min(keep, n)
        rng = self.rng(kind + ":sample")
        drawn = set(rng.sample(range(keep, len(mutants)), n - keep))
        return mutants[:keep] + [m for i, m in enumerate(mutants) if i in drawn]

    # -- the kinds ------------------------------------------------------------------------------
    def kind_lists(self):
        kind, rng = "lists", self.rng("lists")
        rgb, depth = (self.read(os.path.join(self.seq, f)) for f in ("rgb.txt", "depth.txt"))
        depth_mutants = dict(text_mutants(depth, random.Random(rng.random())))
        mutants = []
        for i, (name, content) in enumerate(text_mutants(rgb, rng)):
            target = "rgb.txt" if i % 2 == 0 else "depth.txt"
            if target == "depth.txt":
                content = depth_mutants[name]
            mutants.append((target + ":" + name, target, content))
        # Two frames of one stamp with different files; a line naming an image that is not there.
        mutants.append(("rgb.txt:same-stamp-two-files", "rgb.txt",
                        changed(rgb, rgb.replace(b"1700000000.033333 rgb", b"1700000000.000000 rgb"))))
        mutants.append(("depth.txt:unknown-image", "depth.txt",
                        changed(depth, depth.replace(b"depth/1700000000.066667.png", b"depth/nothere.png"))))
        for i, (name, target, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            seq = self.mirror(self.seq, os.path.join(d, "seq"), {target: content})
            self.add(kind, name, self.slam_argv(seq, os.path.join(d, "out")), [target])
        # The associations file (--associations), its own reader.
        assoc = b"# rgb_stamp rgb_file depth_stamp depth_file\n" + b"".join(
            b"%s rgb/%s.png %s depth/%s.png\n" % (s, s, s, s)
            for s in (l.split()[0] for l in rgb.split(b"\n") if l and not l.startswith(b"#")))
        for j, (name, content) in enumerate([("associations:garbage-bytes", garble(assoc, rng, 16)),
                                             ("associations:duplicated-line", duplicate_line(assoc, rng))]):
            d = self.case_dir(kind, 20 + j)
            path = os.path.join(d, "associations.txt")
            self.place(path, content)
            self.add(kind, name, self.slam_argv(self.seq, os.path.join(d, "out")) + ["--associations", path],
                     ["associations.txt"])

    def kind_png(self):
        kind, rng = "png", self.rng("png")
        stamp = "1700000000.066667"
        targets = [("rgb/%s.png" % stamp, "slam"), ("depth/%s.png" % stamp, "slam"),
                   ("gt/masks/%s.png" % stamp, "detect")]
        mutants = []
        for t, (target, app) in enumerate(targets):
            data = self.read(os.path.join(self.seq, target))
            mutants += [
                ("%s:truncated-half" % target, target, app, truncate(data, 0.5)),
                ("%s:header-bit-flips" % target, target, app, flip_bits(data, rng, 2, 8, 33)),
                ("%s:data-bit-flips" % target, target, app, flip_bits(data, rng, 4, 40)),
                ("%s:garbage" % target, target, app, bytes(rng.randrange(256) for _ in range(len(data) // 8))),
            ]
        depth = self.read(os.path.join(self.seq, targets[1][0]))
        mutants = [
            ("rgb:empty", targets[0][0], "slam", b""),
            ("depth:folder", targets[1][0], "slam", DIR),
            ("gt-mask:missing", targets[2][0], "detect", MISSING),
            ("depth:signature-only", targets[1][0], "slam", depth[:8]),
            ("depth:8-bit-image", targets[1][0], "slam", png_bytes(640, 480, 8, 0, 40)),
            ("depth:64x48-image", targets[1][0], "slam", png_bytes(64, 48, 16, 0, 5000)),
            ("depth:header-30000x30000", targets[1][0], "slam",
             png_bytes(30000, 30000, 16, 0, idat=zlib.compress(b"\x00" * 1000))),
            ("gt-mask:colour-image", targets[2][0], "detect", png_bytes(640, 480, 8, 2, 1)),
            ("gt-mask:1x1", targets[2][0], "detect", png_bytes(1, 1, 8, 0, 1)),
        ] + mutants
        for i, (name, target, app, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            seq = self.mirror(self.seq, os.path.join(d, "seq"), {target: content})
            out = os.path.join(d, "out")
            argv = self.slam_argv(seq, out) if app == "slam" else [self.a.detect, seq, out, "--max-frames", "6"]
            self.add(kind, name, argv, [os.path.basename(target), "masks"])

    def kind_ply(self):
        kind, rng = "ply", self.rng("ply")
        asc, binary = TINY_PLY_ASCII, tiny_ply_binary()
        header_end = binary.index(b"end_header") + len(b"end_header\n")
        mutants = [
            ("empty", b""),
            ("folder", DIR),
            ("ascii:vertex-count-1e9", sub(asc, b"element vertex 6", b"element vertex 1000000000")),
            ("binary:vertex-count-1e9", tiny_ply_binary(vertex_count=1000000000)),
            ("ascii:face-index-out-of-range", sub(asc, b"3 3 5 4", b"3 3 5 4000000")),
            ("binary:face-index-negative", tiny_ply_binary(faces=[(0, 1, 2), (0, 2, -7)])),
            ("ascii:truncated-body", truncate(asc, 0.8)),
            ("binary:truncated-body", binary[: header_end + 30]),
            ("ascii:vertex-count-negative", sub(asc, b"element vertex 6", b"element vertex -6")),
            ("ascii:face-of-200-vertices", sub(asc, b"3 3 5 4", b"200 3 5 4")),
            ("ascii:coordinate-nan", sub(asc, b"1 1 1 30", b"nan 1 1 30")),
            ("ascii:coordinate-1e308", sub(asc, b"1 1 1 30", b"1e308 1 1 30")),
            ("ascii:header-bit-flips", flip_bits(asc, rng, 3, 0, asc.index(b"end_header"))),
            ("binary:header-bit-flips", flip_bits(binary, rng, 3, 0, header_end)),
            ("binary:body-bit-flips", flip_bits(binary, rng, 6, header_end)),
            ("ascii:garbage-bytes", garble(asc, rng, 20)),
            ("binary:garbage-after-header", binary[:header_end] + bytes(rng.randrange(256) for _ in range(64))),
            ("ascii:10MB-line", long_line(asc, rng)),
            ("ascii:no-end_header", sub(asc, b"end_header", b"end_headr")),
            ("ascii:unknown-property-type", sub(asc, b"property float z", b"property quad z")),
        ]
        for i, (name, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            folder = self.mirror(self.view_base, os.path.join(d, "run"), {"map.ply": content})
            self.add_view(kind, "map.ply:" + name, folder, d, ["map.ply"])

    def kind_npz(self):
        kind, rng = "npz", self.rng("npz")
        data = self.read(self.model)
        with zipfile.ZipFile(self.model) as z:
            members = {n: z.read(n) for n in z.namelist()}
        info = zipfile.ZipFile(self.model).getinfo("v_template.npy")
        data_start = info.header_offset + 30 + len(info.filename) + len(info.extra)

        def changed(name, header_from=None, header_to=None, payload=None):
            m = dict(members)
            header, body = npy_split(m[name])
            if header_from is not None:
                assert header_from in header, (name, header)
                header = header.replace(header_from, header_to)
            m[name] = npy_join(header, body if payload is None else payload(body))
            return m

        def int32_at(body, index, value):
            b = bytearray(body)
            b[4 * index:4 * index + 4] = struct.pack("<i", value)
            return bytes(b)

        structured = [
            ("member-f.npy-removed", {k: v for k, v in members.items() if k != "f.npy"}),
            ("v_template-shape-1e9", changed("v_template.npy", "(13380, 3)", "(1000000000, 3)")),
            ("v_template-shape-13380x2", changed("v_template.npy", "(13380, 3)", "(13380, 2)")),
            ("f-index-out-of-range", changed("f.npy", payload=lambda b: int32_at(b, 5, 2_000_000_000))),
            ("kintree-parent-out-of-range", changed("kintree_table.npy", payload=lambda b: int32_at(b, 7, 1000))),
            ("kintree-parent-cycle", changed("kintree_table.npy", payload=lambda b: int32_at(b, 3, 3))),
            ("weights-nan", changed("weights.npy", payload=lambda b: b"\x00\x00\xc0\x7f" * (len(b) // 4))),
            ("J_regressor-complex-dtype", changed("J_regressor.npy", "'<f4'", "'<c8'")),
            ("shapedirs-0-coefficients", changed("shapedirs.npy", "(13380, 3, 10)", "(13380, 3, 0)",
                                                 payload=lambda b: b"")),
            ("v_template-payload-short", changed("v_template.npy", payload=lambda b: b[:1000])),
        ]
        raw = [
            ("empty", b""),
            ("missing", MISSING),
            ("folder", DIR),
            ("truncated-half", truncate(data, 0.5)),
            ("deflate-data-bit-flips", crc_broken(flip_bits(data, rng, 4, data_start, data_start + 50000))),
            ("garbage", garble(data, rng, 4096)),
            ("zip-header-bit-flips", flip_bits(data, rng, 2, 0, 30)),
            ("truncated-at-100-bytes", data[:100]),
        ]
        # Kept: six raw ones and the four structured ones most likely to crash; the rest drawn.
        mutants = raw[:6] + structured[1:2] + structured[3:6] + raw[6:] + structured[:1] + structured[2:3] + structured[6:]
        for i, (name, content) in enumerate(self.sample(kind, mutants, keep=10)):
            d = self.case_dir(kind, i)
            path = os.path.join(d, "model.npz")
            if isinstance(content, dict):
                write_npz(path, content)
            else:
                self.place(path, content)
            self.add(kind, "model.npz:" + name, [self.a.body, "mesh", os.path.join(d, "out.obj"), "--model", path,
                                                 "--pose", "walk"], ["model.npz"])

    def kind_config(self):
        kind, rng = "config", self.rng("config")
        mutants = text_mutants(SLAM_CONFIG, rng) + [
            ("key-without-value", sub(SLAM_CONFIG, b"map.fuse_every 5", b"map.fuse_every")),
            ("binary-zero-bytes", sub(SLAM_CONFIG, b"0.03", b"0\x00\x003")),
        ]
        self.add_file_cases(kind, mutants, "slam.cfg",
                            lambda d, path: self.slam_argv(self.seq, os.path.join(d, "out")) + ["--config", path])

    def kind_camera(self):
        kind, rng = "camera", self.rng("camera")
        cam = self.read(os.path.join(self.seq, "camera.txt"))
        mutants = [m for m in text_mutants(cam, rng) if m[0] not in ("missing",)] + [
            ("fx-twice", sub(cam, b"fx 535.4", b"fx 535.4\nfx 600")),
            ("unknown-key", cam + b"k1 0.2\n"),
            ("width-0", sub(cam, b"width 640", b"width 0")),
            ("cx-5000", sub(cam, b"cx 320.1", b"cx 5000")),
        ]
        for i, (name, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            seq = self.mirror(self.seq, os.path.join(d, "seq"), {"camera.txt": content})
            self.add(kind, "camera.txt:" + name, self.slam_argv(seq, os.path.join(d, "out")),
                     ["camera.txt", "calibration"])

    def kind_trajectory(self):
        kind, rng = "trajectory", self.rng("trajectory")
        gt = self.read(os.path.join(self.seq, "groundtruth.txt"))
        est = self.read(os.path.join(self.run_dir, "trajectory.txt"))
        mutants = text_mutants(gt, rng) + [
            ("zero-quaternion", replace_quaternion(gt, b"0 0 0 0")),
            ("quaternion-1e200", replace_quaternion(gt, b"1e200 1e200 1e200 1e200")),
            ("one-pose", b"\n".join(gt.split(b"\n")[:2]) + b"\n"),
            ("all-stamps-equal", equal_stamps(gt)),
        ]
        readers = ["eval-gt", "eval-estimate", "view", "slam-eval"]
        for i, (name, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            reader = readers[i % len(readers)]
            if reader == "view" and not self.xvfb:
                reader = "eval-gt"
            gt_path, est_path = os.path.join(d, "groundtruth.txt"), os.path.join(d, "estimate.txt")
            label = "%s (%s)" % (name, reader)
            if reader == "eval-gt":
                self.place(gt_path, content)
                self.place(est_path, est)
                self.add(kind, "groundtruth.txt:" + label,
                         [self.a.eval, gt_path, est_path, "--rpe", "--delta-frames", "1"], ["groundtruth.txt"])
            elif reader == "eval-estimate":
                self.place(gt_path, gt)
                self.place(est_path, content)
                self.add(kind, "estimate.txt:" + label,
                         [self.a.eval, gt_path, est_path, "--rpe", "--delta-frames", "1"], ["estimate.txt"])
            elif reader == "view":
                folder = self.mirror(self.view_base, os.path.join(d, "run"), {"trajectory.txt": content})
                self.add_view(kind, "trajectory.txt:" + label, folder, d, ["trajectory.txt"])
            else:
                self.place(gt_path, content)
                out = os.path.join(d, "out")
                self.add(kind, "groundtruth.txt:" + label,
                         self.slam_argv(self.seq, out) + ["--eval", gt_path], ["groundtruth.txt"],
                         check=no_folder(out))

    def kind_humans(self):
        kind, rng = "humans", self.rng("humans")
        txt = self.read(os.path.join(self.view_base, "humans.txt"))
        js = self.read(os.path.join(self.view_base, "humans.json"))
        deep = b'{"tracks":' + b"[" * 200000 + b"]" * 200000 + b"}"
        mutants = [
            ("humans.txt", "10MB-line", long_line(txt, rng)),
            ("humans.json", "truncated-half", truncate(js, 0.5)),
            ("humans.txt", "number-nan", replace_number(txt, rng, b"nan")),
            ("humans.json", "pose-of-71-numbers", sub_pattern(js, rb'"pose":\[[^,\]]+,', b'"pose":[', 1)),
            ("humans.json", "nested-200000-deep", deep),
            ("humans.json", "number-1e308", sub_pattern(js, rb'"translation":\[[^,\]]+', b'"translation":[1e308', 1)),
            ("humans.txt", "id-huge", replace_number(txt, rng, b"99999999999", line_pick=1)),
            ("humans.json", "folder", DIR),
            ("humans.json", "bit-flips", flip_bits(js, rng, 4)),
            ("humans.txt", "garbage-bytes", garble(txt, rng, 24)),
            ("humans.json", "NaN-literal", sub(js, b'"timestamp":', b'"timestamp":NaN,"x":', 1)),
            ("humans.json", "id-string", sub(js, b'{"id":1', b'{"id":"1"', 1)),
            ("humans.txt", "duplicated-line", duplicate_line(txt, rng)),
            ("humans.json", "10MB-line", sub(js, b"\n", b"\n" + b" " * LONG_LINE + b"x\n", 1)),
            ("humans.json", "empty", b""),
            ("humans.txt", "folder", DIR),
        ]
        for i, (target, name, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            folder = self.mirror(self.view_base, os.path.join(d, "run"), {target: content})
            self.add_view(kind, "%s:%s" % (target, name), folder, d, [target])

    def kind_pose(self):
        kind, rng = "pose", self.rng("pose")
        mutants = text_mutants(POSE_FILE, rng) + [
            ("unknown-joint", sub(POSE_FILE, b"left_elbow", b"left_elbo")),
            ("three-numbers-missing", sub(POSE_FILE, b"left_knee 0.6 0 0", b"left_knee")),
        ]
        self.add_file_cases(kind, mutants, "pose.txt",
                            lambda d, path: [self.a.body, "mesh", os.path.join(d, "out.ply"), "--model", self.model,
                                             "--pose-file", path])

    def kind_boxes(self):
        kind, rng = "boxes", self.rng("boxes")
        gt_boxes = self.read(os.path.join(self.seq, "gt", "boxes.txt"))
        boxes = self.read(self.boxes)
        file_mutants = dict(text_mutants(boxes, random.Random(rng.random())))
        mutants = []
        for i, (name, content) in enumerate(text_mutants(gt_boxes, rng)):
            if i % 2 == 0:
                mutants.append(("gt/boxes.txt:" + name, "gt", content))
            else:
                mutants.append(("boxes.txt:" + name, "file", file_mutants[name]))
        mutants += [
            ("boxes.txt:corner-1e308", "file", changed(boxes, boxes.replace(b" 119.00 ", b" 1e308 ", 1))),
            ("boxes.txt:corner--1e9", "file", changed(boxes, boxes.replace(b" 5.00 ", b" -1000000000 ", 1))),
            ("gt/boxes.txt:box-outside-image", "gt",
             changed(gt_boxes, gt_boxes.replace(b" 5 168 118 421 ", b" 9000 9000 9900 9900 ", 1))),
        ]
        for i, (name, mode, content) in enumerate(self.sample(kind, mutants)):
            d = self.case_dir(kind, i)
            out = os.path.join(d, "out")
            if mode == "gt":
                seq = self.mirror(self.seq, os.path.join(d, "seq"), {"gt/boxes.txt": content})
                argv = [self.a.detect, seq, out, "--max-frames", "6"]
            else:
                path = os.path.join(d, "boxes.txt")
                self.place(path, content)
                argv = [self.a.detect, self.seq, out, "--detector", "file", "--boxes", path, "--max-frames", "6"]
            self.add(kind, name, argv, ["boxes.txt"])

    def kind_issue(self):
        """The cases issue 14 names, each refused with its key or file named."""
        kind, a = "issue", self.a
        k = [0]

        def d():
            k[0] += 1
            return self.case_dir(kind, k[0])

        def slam_config(line, key):
            c = d()
            self.place(os.path.join(c, "x.cfg"), line.encode() + b"\n")
            out = os.path.join(c, "out")
            self.add(kind, "pf2_slam --config: %s" % line, self.slam_argv(self.seq, out) + ["--config", os.path.join(c, "x.cfg")],
                     [key], expect_error=True, check=no_folder(out))

        for line in ("map.voxel_size 1e-6", "map.truncation 1e9", "map.octomap_resolution 1e-5", "map.voxel_size 100",
                     "map.max_depth -1", "map.fuse_every -1", "run.prefetch_frames -1", "tracker.pyramid_levels 1000"):
            slam_config(line, line.split()[0])
        c = d()
        self.add(kind, "pf2_slam --frames -5", self.slam_argv(self.seq, os.path.join(c, "out"))[:-5] +
                 ["--detector", "none", "--quiet", "--frames", "-5"], ["--frames"], expect_error=True,
                 check=no_folder(os.path.join(c, "out")))
        c = d()
        self.add(kind, "pf2_slam --config DIR", self.slam_argv(self.seq, os.path.join(c, "out")) + ["--config", c],
                 [c], expect_error=True)
        # Lists: two lines of one stamp; every stamp equal.
        rgb = self.read(os.path.join(self.seq, "rgb.txt"))
        lines = rgb.split(b"\n")
        c = d()
        seq = self.mirror(self.seq, os.path.join(c, "seq"), {"rgb.txt": b"\n".join(lines[:5] + lines[4:])})
        self.add(kind, "rgb.txt with one line twice", self.slam_argv(seq, os.path.join(c, "out")), ["rgb.txt"],
                 expect_error=True)
        c = d()
        seq = self.mirror(self.seq, os.path.join(c, "seq"), {
            "rgb.txt": equal_stamps(rgb), "depth.txt": equal_stamps(self.read(os.path.join(self.seq, "depth.txt")))})
        self.add(kind, "rgb.txt/depth.txt all stamps equal", self.slam_argv(seq, os.path.join(c, "out")),
                 ["rgb.txt", "depth.txt"], expect_error=True)
        c = d()
        est = os.path.join(c, "estimate.txt")
        self.place(est, equal_stamps(self.read(os.path.join(self.run_dir, "trajectory.txt"))))
        self.add(kind, "pf2_eval on an estimate whose stamps are all equal",
                 [a.eval, os.path.join(self.seq, "groundtruth.txt"), est], ["estimate.txt"], expect_error=True)
        # camera.txt.
        cam = self.read(os.path.join(self.seq, "camera.txt"))
        for label, content in (("fx twice", sub(cam, b"fx 535.4", b"fx 535.4\nfx 600")),
                               ("fx 1e-9", sub(cam, b"fx 535.4", b"fx 1e-9")),
                               ("cx 5000", sub(cam, b"cx 320.1", b"cx 5000")),
                               ("cy -300", sub(cam, b"cy 247.6", b"cy -300"))):
            c = d()
            seq = self.mirror(self.seq, os.path.join(c, "seq"), {"camera.txt": content})
            self.add(kind, "camera.txt: " + label, self.slam_argv(seq, os.path.join(c, "out")), ["camera.txt"],
                     expect_error=True)
        # pf2_body --shape.
        for shape in ("nan", "1e30", "1,2,3,4,5,-1,-2,-3,-4,-5,1,1"):
            c = d()
            out = os.path.join(c, "x.obj")
            self.add(kind, "pf2_body mesh x.obj --shape " + shape, [a.body, "mesh", out, "--shape", shape],
                     ["shape"], expect_error=True, check=no_file(out))
        # --eval GROUNDTRUTH missing or broken: refused before the run (no output folder).
        for label, content in (("missing", MISSING), ("broken", b"1700000000.0 1 2 3 garbage\n")):
            c = d()
            gt = os.path.join(c, "gt.txt")
            self.place(gt, content)
            out = os.path.join(c, "out")
            self.add(kind, "pf2_slam --eval with a %s file" % label, self.slam_argv(self.seq, out) + ["--eval", gt],
                     ["gt.txt"], expect_error=True, check=no_folder(out))
        # A quaternion whose components overflow its norm (1e200 each) is the same rotation as
        # (0.5, 0.5, 0.5, 0.5): the relative rotation between the two files must be 0.
        c = d()
        qa, qb = os.path.join(c, "half.txt"), os.path.join(c, "huge.txt")
        self.place(qa, b"1 0 0 0 0 0 0 1\n2 0 0 0 0.5 0.5 0.5 0.5\n3 1 0 0 0 0 0 1\n")
        self.place(qb, b"1 0 0 0 0 0 0 1\n2 0 0 0 1e200 1e200 1e200 1e200\n3 1 0 0 0 0 0 1\n")
        self.add(kind, "pf2_eval: quaternion 1e200 1e200 1e200 1e200 read as the rotation it is",
                 [a.eval, qa, qb, "--rpe", "--delta-frames", "1"], ["huge.txt"],
                 check=stdout_says(r"rpe\.rot\.max\s+0\.0+ deg", "the 1e200 quaternion was read as another rotation"))
        # A run whose map is empty (nothing within map.max_depth 0.3 m) says so, or writes a map
        # that pf2_view can show: not a map.ply of 0 vertices without a word.
        c = d()
        out = os.path.join(c, "out")
        self.add(kind, "pf2_slam --set map.max_depth=0.3 (no depth that near): an empty map",
                 [a.slam, self.seq, "-o", out, "--frames", "6", "--detector", "none", "--quiet",
                  "--set", "map.max_depth=0.3", "--set", "map.octomap=false"], ["map.max_depth", "map.ply"],
                 check=empty_map_noted(os.path.join(out, "map.ply")))
        # pf2_view on a PLY header claiming 10^9 vertices: fails fast, names the file.
        c = d()
        folder = self.mirror(self.view_base, os.path.join(c, "run"), {"map.ply": tiny_ply_binary(vertex_count=10 ** 9)})
        self.add_view(kind, "pf2_view: map.ply header claims 10^9 vertices", folder, c, ["map.ply"],
                      expect_error=True, max_seconds=10)
        # A 10 MB garbage line is not echoed whole (config and trajectory; the kinds above try every reader).
        c = d()
        cfg = os.path.join(c, "long.cfg")
        self.place(cfg, long_line(b"run.max_frames 6\n", random.Random(1)))
        self.add(kind, "pf2_slam --config with a 10 MB line", self.slam_argv(self.seq, os.path.join(c, "out")) +
                 ["--config", cfg], ["long.cfg"], expect_error=True)
        c = d()
        gt = os.path.join(c, "long.txt")
        self.place(gt, long_line(self.read(os.path.join(self.seq, "groundtruth.txt")), random.Random(2)))
        self.add(kind, "pf2_eval with a 10 MB line", [a.eval, gt, os.path.join(self.run_dir, "trajectory.txt")],
                 ["long.txt"], expect_error=True)
        # A path with a space is named whole.
        c = d()
        gt = os.path.join(c, "a folder", "ground truth.txt")
        self.place(gt, self.read(os.path.join(self.seq, "groundtruth.txt")) + b"1 2 3\n")
        self.add(kind, "pf2_eval on a broken file whose path has spaces",
                 [a.eval, gt, os.path.join(self.run_dir, "trajectory.txt")], [gt], expect_error=True)
        # Option ranges name the option.
        for opts, key in ((["--rpe", "--delta-frames", "0"], "--delta-frames"), (["--max-diff", "-1"], "--max-diff")):
            c = d()
            self.add(kind, "pf2_eval " + " ".join(opts),
                     [a.eval, os.path.join(self.seq, "groundtruth.txt"), os.path.join(self.run_dir, "trajectory.txt")] + opts,
                     [key], expect_error=True)
        # Every app's --config: a folder, and a garbage line.
        apps = [("pf2_eval", [a.eval, os.path.join(self.seq, "groundtruth.txt"), os.path.join(self.run_dir, "trajectory.txt")]),
                ("pf2_synth", [a.synth, None, "--frames", "2", "--quiet"]),
                ("pf2_detect", [a.detect, self.seq, None, "--max-frames", "2"]),
                ("pf2_body", [a.body, "mesh", None]),
                ("pf2_slam", self.slam_argv(self.seq, None))]
        if self.xvfb:
            apps.append(("pf2_view", self.view_argv(self.view_base, None)))
        for app, argv in apps:
            for label, content in (("folder", DIR), ("garbage line", b"run.max_frames 6\n\x01\x02garbage \xff\xfe line\n")):
                c = d()
                cfg = os.path.join(c, "app.cfg")
                self.place(cfg, content)
                out = {"pf2_body": os.path.join(c, "x.obj"), "pf2_view": os.path.join(c, "shot.png")}.get(
                    app, os.path.join(c, "out"))
                full = [out if x is None else x for x in argv] + ["--config", cfg]
                self.add(kind, "%s --config: %s" % (app, label), full, ["app.cfg"], expect_error=True,
                         view=app == "pf2_view")
        # The other model readers: a garbage YOLO network, a garbage plug-in model, a missing MPFB2 folder.
        c = d()
        onnx = os.path.join(c, "net.onnx")
        self.place(onnx, bytes(random.Random(3).randrange(256) for _ in range(5000)))
        self.add(kind, "pf2_detect --detector yolo with a garbage .onnx",
                 [a.detect, self.seq, os.path.join(c, "out"), "--detector", "yolo", "--yolo-model", onnx,
                  "--max-frames", "2"], ["net.onnx"], expect_error=True)
        c = d()
        cfgnet = os.path.join(c, "net.cfg")
        self.place(cfgnet, b"[net]\nwidth=416\nheight\n[convolutional]\nfilters=abc\n")
        self.add(kind, "pf2_detect --detector yolo with a broken Darknet .cfg",
                 [a.detect, self.seq, os.path.join(c, "out"), "--detector", "yolo", "--yolo-model", cfgnet,
                  "--yolo-weights", cfgnet, "--max-frames", "2"], ["net.cfg"], expect_error=True)
        c = d()
        model = os.path.join(c, "model.json")
        self.place(model, b'{"format": "graph-model", "modelTopology": [1, 2, ')
        self.add(kind, "pf2_detect --detector selfie with a broken model.json",
                 [a.detect, self.seq, os.path.join(c, "out"), "--detector", "selfie", "--model", model,
                  "--max-frames", "2"], ["model.json"], expect_error=True)
        c = d()
        self.add(kind, "pf2_body convert-mpfb2 on a folder without MakeHuman data",
                 [a.body, "convert-mpfb2", c, os.path.join(c, "out.npz")], [c], expect_error=True,
                 check=no_file(os.path.join(c, "out.npz")))

    # -- running --------------------------------------------------------------------------------
    def run_case(self, case):
        for attempt in range(3):
            status, timed_out, err = self.run_once(case)
            # xvfb-run -a can lose the race for a display number to another xvfb-run on the
            # machine, and an app being relinked cannot be started (exit 126/127 from the
            # wrapper's exec): no outcome of the app's, so the run is tried again.
            exec_failed = (not timed_out and os.WIFEXITED(status) and os.WEXITSTATUS(status) in (126, 127)
                           and re.search(rb"(?m)^(sh: \d+: exec: |/usr/bin/xvfb-run: \d+: )", err))
            if case.view and b"Xvfb failed to start" in err:
                continue
            if exec_failed and attempt < 2:
                time.sleep(30)
                continue
            break
        self.classify(case, status, timed_out, err)

    def run_once(self, case):
        wrapped = ["/bin/sh", "-c", 'ulimit -v %d; ulimit -c 0; exec "$@"' % MEMORY_LIMIT_KB, "sh"] + case.argv
        stem = os.path.join(self.work, "logs", "%s-%03d" % (case.kind, self.cases.index(case)))
        err_path, case.out_path = stem + ".err", stem + ".out"
        lock = self.view_lock if case.view else None
        if lock:
            lock.acquire()
        try:
            start = time.monotonic()
            with open(err_path, "wb") as err, open(case.out_path, "wb") as out:
                p = subprocess.Popen(wrapped, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                     cwd=case.cwd or self.work, start_new_session=True)
                timed_out = False
                while True:
                    pid, status, _ = os.wait4(p.pid, os.WNOHANG)
                    if pid:
                        break
                    if time.monotonic() - start > self.a.timeout:
                        timed_out = True
                        os.killpg(p.pid, signal.SIGKILL)
                        _, status, _ = os.wait4(p.pid, 0)
                        break
                    time.sleep(0.02)
                p.returncode = 0  # reaped here; keep Popen from waiting again
            case.seconds = time.monotonic() - start
        finally:
            if lock:
                lock.release()
        with open(err_path, "rb") as f:
            return status, timed_out, f.read()

    def classify(self, case, status, timed_out, err):
        lines = [l for l in err.split(b"\n") if l.strip()]
        first = lines[0].decode("utf-8", "replace") if lines else ""
        case.detail = first[:300] + (" ... (%d characters)" % len(first) if len(first) > 300 else "")
        if timed_out:
            case.outcome, case.detail = "hang", "killed after %d s" % self.a.timeout
            return
        if os.WIFSIGNALED(status):
            case.code = -os.WTERMSIG(status)
            case.outcome = "crash"
            case.detail = "signal %d (%s); %s" % (-case.code, signal.Signals(-case.code).name, case.detail)
            return
        case.code = os.WEXITSTATUS(status)
        if case.code > 1 or b"terminate called" in err:
            case.outcome = "crash"
            case.detail = "exit status %d; %s" % (case.code, case.detail)
            return
        if case.code == 0:
            case.outcome = "silent" if case.expect_error else "ok"
            if case.expect_error:
                case.detail = "exit 0: accepted what must be refused"
        elif len(lines) != 1:
            case.outcome = "messy"
            case.detail = "%d stderr lines: %s" % (len(lines), " | ".join(
                l.decode("utf-8", "replace")[:150] for l in lines[:4]))
        elif len(lines[0]) >= MAX_LINE:
            case.outcome = "messy"
        elif re.search(rb"[\x00-\x08\x0b-\x1f\x7f]", lines[0]):
            case.outcome = "messy"
            case.detail = "control characters in: " + repr(lines[0][:200])
        elif not any(n in first for n in case.names):
            case.outcome = "unnamed"
            case.detail = "names none of %s: %s" % (", ".join(case.names), case.detail)
        else:
            case.outcome = "clean"
        if case.outcome in ("ok", "clean") and case.max_seconds and case.seconds > case.max_seconds:
            case.outcome = "slow"
            case.detail = "%.1f s (limit %d s): %s" % (case.seconds, case.max_seconds, case.detail)
        if case.outcome in ("ok", "clean") and case.check:
            problem = case.check(case)
            if problem:
                case.outcome, case.detail = "silent", problem + "; " + case.detail


def replace_quaternion(traj, q):
    lines, idx = data_lines(traj)
    i = idx[len(idx) // 2]
    f = lines[i].split()
    lines[i] = b" ".join(f[:4]) + b" " + q
    return b"\n".join(lines)


def equal_stamps(data):
    lines, idx = data_lines(data)
    stamp = lines[idx[0]].split()[0]
    for i in idx:
        lines[i] = stamp + b" " + lines[i].split(None, 1)[1]
    return b"\n".join(lines)


def sub(data, old, new, count=-1):
    """data with old replaced by new; old must be there (else the mutant would test nothing)."""
    if old not in data:
        raise AssertionError("mutant not made: %r not in the original" % old[:60])
    return data.replace(old, new, count)


def sub_pattern(data, pattern, new, count=0):
    """data with the regular expression's matches replaced by new; it must match (as in sub)."""
    mutant, made = re.subn(pattern, new, data, count)
    if not made:
        raise AssertionError("mutant not made: %r matches nothing in the original" % pattern[:60])
    return mutant


def crc_broken(npz):
    """The mutant, after making sure that a zip reader sees it as corrupt (a CRC or inflate error)."""
    import io
    try:
        bad = zipfile.ZipFile(io.BytesIO(npz)).testzip()
    except (zipfile.BadZipFile, zlib.error, OSError):
        bad = "unreadable"
    if bad is None:
        raise AssertionError("the flipped .npz still passes Python's zip test: choose other bits")
    return npz


def stdout_says(pattern, problem):
    """An accepted run printed what it must (a refusal is judged as any other)."""
    def check(case):
        if case.code != 0:
            return None
        with open(case.out_path, "rb") as f:
            text = f.read().decode("utf-8", "replace")
        return None if re.search(pattern, text) else problem
    return check


def empty_map_noted(ply):
    """exit 0 with a map.ply of 0 vertices needs a word about it on stdout or stderr."""
    def check(case):
        if case.code != 0 or not os.path.exists(ply):
            return None
        with open(ply, "rb") as f:
            head = f.read(400)
        if b"element vertex 0\n" not in head:
            return None
        said = b""
        for path in (case.out_path, case.out_path[:-4] + ".err"):
            with open(path, "rb") as f:
                said += f.read()
        if re.search(rb"(?i)empty|no vertices|0 vertices|no map", said):
            return None
        return "wrote a map.ply of 0 vertices (which pf2_view refuses) without a word"
    return check


def changed(original, mutant):
    """The mutant, after making sure the replacement that made it found its text."""
    if mutant == original:
        raise AssertionError("mutant equal to its original: the test's replacement found nothing")
    return mutant


def no_folder(path):
    """A refused run leaves no output folder (bad input is found before the run)."""
    return lambda case: ("exit 1 but created the output folder %s" % path
                         if case.code == 1 and os.path.exists(path) else None)


def no_file(path):
    """A refused run writes no output file."""
    return lambda case: "exit 1 but wrote %s" % path if case.code == 1 and os.path.exists(path) else None


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for app in ("slam", "eval", "synth", "detect", "body"):
        p.add_argument("--" + app, required=True, help="path of pf2_" + app)
    p.add_argument("--view", default="", help="path of pf2_view (optional: without it, or without "
                   "xvfb-run, the pf2_view cases are skipped)")
    p.add_argument("--repo", required=True, help="repository root (for the shipped body model)")
    p.add_argument("--work", required=True, help="work folder (emptied first)")
    p.add_argument("--per-kind", type=int, default=12, help="mutants per input kind (default 12)")
    p.add_argument("--timeout", type=float, default=60, help="seconds before a run counts as a hang")
    p.add_argument("--jobs", type=int, default=2, help="runs at a time (default 2)")
    p.add_argument("--seed", type=int, default=14, help="seed of the mutants (default 14)")
    p.add_argument("--kinds", default="", help="comma-separated kinds to run (default all)")
    args = p.parse_args()
    for app in ("slam", "eval", "synth", "detect", "body", "view"):
        path = getattr(args, app)
        if app == "view" and not path:
            continue
        if not os.access(path, os.X_OK):
            print("skipped: %s is not an executable" % path)
            return 77
        setattr(args, app, os.path.abspath(path))

    test = Test(args)
    t0 = time.monotonic()
    test.setup()
    os.makedirs(os.path.join(test.work, "logs"))
    kinds = ["lists", "png", "ply", "npz", "config", "camera", "trajectory", "humans", "pose", "boxes", "issue"]
    chosen = [k for k in args.kinds.split(",") if k] or kinds
    for k in chosen:
        getattr(test, "kind_" + k)()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        list(pool.map(test.run_case, test.cases))

    # The table.
    used = [o for o in OUTCOMES]
    width = max(len(k) for k in chosen + ["total"]) + 2
    print("mutation test: %d runs in %.0f s (seed %d, at most %d mutants per kind, timeout %g s)"
          % (len(test.cases), time.monotonic() - t0, args.seed, args.per_kind, args.timeout))
    print("| kind".ljust(width + 2) + " | " + " | ".join(used) + " |")
    print("|" + "-" * (width + 1) + "|" + "|".join("-" * (len(o) + 2) for o in used) + "|")
    totals = {o: 0 for o in used}
    for k in chosen:
        row = [c for c in test.cases if c.kind == k]
        counts = {o: sum(1 for c in row if c.outcome == o) for o in used}
        for o in used:
            totals[o] += counts[o]
        print("| " + k.ljust(width) + " | " + " | ".join(str(counts[o]).rjust(len(o)) for o in used) + " |")
    print("| " + "total".ljust(width) + " | " + " | ".join(str(totals[o]).rjust(len(o)) for o in used) + " |")
    if test.skipped:
        print("skipped (no pf2_view or no xvfb-run): %d pf2_view cases" % len(test.skipped))
    bad = [c for c in test.cases if c.outcome in FAILING]
    if bad:
        print("\nnot ok or clean (%d):" % len(bad))
        for c in bad:
            print("%-7s %s/%s (%.1f s): %s" % (c.outcome, c.kind, c.name, c.seconds, c.detail))
            print("        $ " + " ".join(shlex.quote(x) for x in c.argv))
    if os.environ.get("PF2_MUTATION_VERBOSE"):
        print("\nall cases:")
        for c in test.cases:
            print("%-7s %s/%s (%.1f s): %s" % (c.outcome, c.kind, c.name, c.seconds, c.detail))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
