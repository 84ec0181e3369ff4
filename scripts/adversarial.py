#!/usr/bin/python3
"""Held-out adversarial table: hostile command lines against the built program, each classified.

    /usr/bin/python3 scripts/adversarial.py [--program build/cli/icobrdf] [--only SUBSTRING] [--verbose]

Each case states what it expects: a refusal (exit code, a pattern of its one-line message, no output file,
nothing on stdout) or a result (exit 0, checked against a value derived here: a closed form, or another
consumer of the same material). Each runs in a scratch folder with a time limit (timeout) and an address
space limit (RLIMIT_AS), and is classified:

  OK    a clear one-line error with the expected exit code and no partial output; or a correct result
  weak  works, but the exit code or the message is not the one expected (still one line, nothing written)
  bad   exit 0 with a wrong result, a crash or an internal error (exit 70 / 134 / a signal), a hang, a
        multi-line message or a stack trace, partial output, more memory than the limit allows

Not part of CTest (about two minutes on two cores); docs/reliability.md records its last result. Exit code:
the number of bad cases (0: none).
"""
import argparse
import json
import math
import os
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time

LIMIT_SECONDS = 60            # a hang: no case takes a tenth of this when it works
LIMIT_AS_BYTES = 8 << 30      # address space per case: the largest valid case (a level-5 LUT) needs 2 GB
HUGE_RSS_BYTES = 3 << 30      # resident memory beyond this, for a case that is not a large valid request, is bad
SAMPLE_SIGMAS = 5.0           # a sample mean within 5 standard errors of the albedo
READ_BACK_REL = 0.05          # an exported file read back agrees with eval of the bank within 5 % (grid and bins)
LAMBERT = 0.5 / math.pi       # f of model:lambert:albedo=0.5

PROGRESS_LINE = re.compile(r"^[^:]+: ([0-9]+% after|done after|stopped after)")
TRACE = re.compile(r"terminate called|Assertion|Segmentation|what\(\)|AddressSanitizer|runtime error:|Traceback|#0 ")


class Case:
    def __init__(self, name, args, expect="fail", code=None, pattern=None, output=None, check=None, stdin=None,
                 stdout=None, send=None, env=None, fsize=None, limit=LIMIT_SECONDS, big=False, feed=None):
        self.name, self.args, self.expect, self.code, self.pattern = name, args, expect, code, pattern
        self.output, self.check, self.stdin, self.stdout, self.send = output, check, stdin, stdout, send
        self.env, self.fsize, self.limit, self.big, self.feed = env or {}, fsize, limit, big, feed
        # bank build reports each material on stderr before its final line; a stop signal with nothing
        # unfinished ends silently (docs/reliability.md): those lines are not the error line.
        self.report_lines = args[:2] == ["bank", "build"] or (args[:1] == ["--memory-budget"] and args[2:4] == ["bank", "build"])
        self.silent_ok = send is not None


def run(program, case, folder):
    """Runs one case; returns a dict of what happened."""
    env = dict(os.environ, **case.env)
    env.setdefault("ICOBRDF_PROGRESS_DELAY", "1000")  # progress lines would add lines to stderr

    def limits():
        resource.setrlimit(resource.RLIMIT_AS, (LIMIT_AS_BYTES, LIMIT_AS_BYTES))
        if case.fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (case.fsize, case.fsize))
        if case.stdout == "closed":
            os.close(1)

    out_target = subprocess.PIPE
    if case.stdout == "full":
        out_target = open("/dev/full", "wb")
    elif case.stdout == "closed":
        out_target = None
    if case.feed:  # a writer for a FIFO: opens it (waiting for the reader), writes, closes
        def feed():
            try:
                with open(os.path.join(folder, case.feed[0]), "wb") as f:
                    f.write(case.feed[1])
            except BrokenPipeError:  # the program refused the input and closed the FIFO before the end
                pass
        threading.Thread(target=feed, daemon=True).start()
    start = time.monotonic()
    p = subprocess.Popen([program] + case.args, cwd=folder, env=env, stdin=subprocess.DEVNULL, stdout=out_target,
                         stderr=subprocess.PIPE, preexec_fn=limits)
    got = {}

    def drain(name, stream):
        got[name] = stream.read()

    readers = [threading.Thread(target=drain, args=("err", p.stderr))]
    if out_target == subprocess.PIPE:
        readers.append(threading.Thread(target=drain, args=("out", p.stdout)))
    for t in readers:
        t.start()
    done = threading.Event()
    timed_out = []

    def kill():
        if not done.is_set():
            timed_out.append(True)
            os.kill(p.pid, signal.SIGKILL)

    def send():
        if not done.is_set():
            os.kill(p.pid, case.send[1])

    timers = [threading.Timer(case.limit, kill)]
    if case.send:
        timers.append(threading.Timer(case.send[0], send))
    for t in timers:
        t.start()
    _, status, usage = os.wait4(p.pid, 0)  # this child's own peak resident set
    done.set()
    p.returncode = os.waitstatus_to_exitcode(status)
    for t in timers:
        t.cancel()
    for t in readers:
        t.join()
    if case.stdout == "full":
        out_target.close()
    return {"rc": p.returncode, "out": got.get("out") or b"", "err": got["err"].decode("utf-8", "replace"),
            "seconds": time.monotonic() - start, "timed_out": bool(timed_out), "rss": usage.ru_maxrss * 1024}


def classify(case, r, folder):
    """(class, reason) of one case's run."""
    lines = [l for l in r["err"].splitlines() if l and not PROGRESS_LINE.match(l)]
    errors = [l for l in lines if "warning:" not in l]
    if case.report_lines:
        errors = [l for l in errors if l.startswith("icobrdf:")]
    if r["timed_out"]:
        return "bad", "no answer within %d s" % case.limit
    if r["rc"] < 0 and case.send is None:
        return "bad", "killed by signal %d" % -r["rc"]
    if r["rc"] in (70, 134, 139):
        return "bad", "internal error or crash (exit %d)" % r["rc"]
    if TRACE.search(r["err"]):
        return "bad", "a trace on stderr: " + r["err"][:200]
    if r["rss"] > HUGE_RSS_BYTES and not case.big:
        return "bad", "peak resident memory %.1f GB" % (r["rss"] / 2**30)
    out_path = os.path.join(folder, case.output) if case.output else None
    if case.expect == "fail" or (case.expect == "either" and r["rc"] != 0):
        if r["rc"] == 0:
            return "bad", "exit 0 where a refusal was expected; stdout %r" % r["out"][:120]
        if len(errors) != 1 and not (case.silent_ok and not errors):
            return "bad", "%d lines on stderr: %r" % (len(errors), r["err"][:300])
        if r["out"] and case.stdout is None and not case.report_lines:  # bank build's table reports the failed row
            return "bad", "partial output on stdout (%d bytes)" % len(r["out"])
        if out_path and os.path.exists(out_path):
            return "bad", "the output file exists after a refusal"
        leftovers = [n for n in os.listdir(folder) if ".tmp-" in n]
        if leftovers:
            return "bad", "temporary files left: %s" % leftovers
        codes = case.code if isinstance(case.code, tuple) else (case.code,)
        if case.code is not None and r["rc"] not in codes:
            return "weak", "exit %d, expected %s: %s" % (r["rc"], case.code, errors[0] if errors else "")
        if case.pattern and not (errors and re.search(case.pattern, errors[0])):
            return "weak", "message lacks /%s/: %s" % (case.pattern, errors[0] if errors else "")
        return "OK", errors[0] if errors else "exit %d, nothing said" % r["rc"]
    if r["rc"] != 0:
        return ("weak" if len(errors) == 1 else "bad"), "exit %d where a result was expected: %s" % (r["rc"], r["err"][:200])
    if case.check:
        problem = case.check(r, folder)
        if problem:
            return "bad", problem
    return "OK", "result checked" if case.check else "exit 0"


# ---- checks of results -------------------------------------------------------------------------------------

def csv_rows(text):
    rows = [l.split(",") for l in text.decode().strip().splitlines()]
    return rows[0], [[float(x) for x in row] for row in rows[1:]]


def eval_equals(want, rel=1e-12):
    def check(r, folder):
        _, rows = csv_rows(r["out"])
        got = [row[-1] for row in rows]
        bad = [g for g in got if not (abs(g - want) <= rel * abs(want))]
        return "eval gave %s, expected %r" % (bad[:3], want) if bad or not got else None
    return check


def output_starts(name, magic):
    def check(r, folder):
        path = os.path.join(folder, name)
        if not os.path.exists(path):
            return "exit 0 but no %s" % name
        with open(path, "rb") as f:
            head = f.read(len(magic))
        return None if head == magic else "%s starts with %r, expected %r" % (name, head, magic)
    return check


def lines_on_stdout(n):
    def check(r, folder):
        got = r["out"].count(b"\n")
        return None if got == n else "%d lines on stdout, expected %d" % (got, n)
    return check


def albedo_near(want, tol):
    def check(r, folder):
        got = json.loads(r["out"])["black_sky"][0]["albedo"][0]
        return None if abs(got - want) <= tol else "albedo %r, expected %r within %r" % (got, want, tol)
    return check


# ---- fixtures ----------------------------------------------------------------------------------------------

def write(folder, name, data):
    path = os.path.join(folder, name)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())
    return path


def scene(body, bank_extra=""):
    return ("[bank]\nlevel = 2\nlevels = [2]\norder_max = 4\ntarget = 0.05\nholdout_pairs = 256\n" + bank_extra +
            "\n[[material]]\nname = \"m\"\nsource = \"model:lambert:albedo=0.5\"\n" + body)


def make_fixtures(program, folder, repo):
    def icobrdf(*args):
        subprocess.run([program, "--no-progress"] + list(args), cwd=folder, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)

    write(folder, "pair.csv", "theta_i,phi_i,theta_r,phi_r\n20,0,25,170\n")
    write(folder, "pairs.csv", "theta_i,phi_i,theta_r,phi_r\n" + "".join(
        "%d,%d,%d,%d\n" % (t, 7 * t, 60 - t, 180 - 5 * t) for t in range(5, 56, 10)))
    icobrdf("fit", "model:lambert:albedo=0.5", "--level", "2", "--order", "2", "-o", "modes.h5")
    hybrid = scene("", 'representations = ["hybrid"]\n').replace("model:lambert:albedo=0.5", "model:0.3*lambert+0.7*ggx:alpha=0.2")
    write(folder, "hybrid.toml", hybrid)
    icobrdf("bank", "build", "hybrid.toml", "-o", "hybrid.h5")
    # A build long enough (3.4 s here) that a signal sent at 0.3 s finds it running (a scene of three materials,
    # 0.4 s, did not always: the build could end first).
    write(folder, "many.toml", hybrid + "".join('\n[[material]]\nname = "m%d"\nsource = "model:0.3*lambert+0.7*ggx:alpha=0.%02d"\n' % (k, k)
                                                for k in range(10, 42, 2)))
    write(folder, "lobe.toml", scene("", 'representations = ["half-angle"]\ntarget = 0.5\n').replace(
        "target = 0.05\n", "").replace("model:lambert:albedo=0.5", "model:ggx:alpha=0.3"))
    icobrdf("bank", "build", "lobe.toml", "-o", "lobe.h5")
    icobrdf("export", "model:ggx:alpha=0.3", "--format", "rgl", "-o", "ggx.bsdf")
    good = open(os.path.join(folder, "ggx.bsdf"), "rb").read()
    write(folder, "truncated.bsdf", good[: len(good) // 3])
    write(folder, "garbage.bsdf", bytes(range(256)) * 8)
    header = bytearray(good[:64])
    write(folder, "header-only.bsdf", bytes(header))
    bank = open(os.path.join(folder, "modes.h5"), "rb").read()
    write(folder, "truncated.h5", bank[: len(bank) // 2])
    write(folder, "text.h5", "this is no HDF5 file\n")
    flipped = bytearray(bank)
    for k in range(len(flipped) // 3, len(flipped) // 3 + 64):
        flipped[k] ^= 0xFF
    write(folder, "flipped.h5", bytes(flipped))
    # MERL tables: header of three int32 dims, then 3 x dims doubles.
    write(folder, "empty.binary", b"")
    write(folder, "zero-dims.binary", struct.pack("<3i", 0, 0, 0))
    write(folder, "huge-dims.binary", struct.pack("<3i", 90, 90, 2**30) + b"\0" * 64)
    write(folder, "short.binary", struct.pack("<3i", 90, 90, 180) + b"\0" * 1000)
    write(folder, "negative-dims.binary", struct.pack("<3i", -90, 90, 180))
    # CSV samples.
    write(folder, "empty.csv", "")
    write(folder, "header.csv", "theta_i,phi_i,theta_r,phi_r,f\n")
    write(folder, "nan.csv", "theta_i,phi_i,theta_r,phi_r,f\n10,0,10,180,nan\n20,0,20,180,0.1\n")
    write(folder, "huge-f.csv", "theta_i,phi_i,theta_r,phi_r,f\n" + "".join(
        "%d,0,%d,180,1e308\n" % (t, t) for t in range(5, 80, 5)))
    write(folder, "theta91.csv", "theta_i,phi_i,theta_r,phi_r,f\n91,0,10,180,0.1\n")
    write(folder, "binary.csv", bytes(range(1, 256)) * 4)
    write(folder, "long-line.csv", "theta_i,phi_i,theta_r,phi_r,f\n" + "1" * (2 << 20) + "\n")
    write(folder, "utf16.csv", "theta_i,phi_i,theta_r,phi_r,f\n10,0,10,180,0.1\n".encode("utf-16"))
    write(folder, "pairs-1e308.csv", "theta_i,phi_i,theta_r,phi_r\n1e308,0,10,180\n")
    write(folder, "pairs-nan.csv", "theta_i,phi_i,theta_r,phi_r\nnan,0,10,180\n")
    write(folder, "pairs-minus0.csv", "theta_i,phi_i,theta_r,phi_r\n-0,-0,-0,-0\n")
    # Scenes.
    write(folder, "empty.toml", "")
    write(folder, "binary.toml", bytes(range(256)))
    write(folder, "unclosed.toml", "[bank\nlevels = [2]\n")
    write(folder, "level12.toml", scene("").replace("levels = [2]", "levels = [12]"))
    write(folder, "order200.toml", scene("").replace("order_max = 4", "order_max = 200"))
    write(folder, "target-nan.toml", scene("").replace("target = 0.05", "target = nan"))
    write(folder, "target-neg.toml", scene("").replace("target = 0.05", "target = -1"))
    write(folder, "holdout-huge.toml", scene("").replace("holdout_pairs = 256", "holdout_pairs = 1000000000000000000"))
    write(folder, "missing-source.toml", scene("").replace("model:lambert:albedo=0.5", "nowhere/missing.binary"))
    write(folder, "level8.toml", scene("").replace("levels = [2]", "levels = [8]").replace("level = 2", "level = 8"))
    write(folder, "dup.toml", scene("\n[[material]]\nname = \"m\"\nsource = \"model:lambert\"\n"))
    # CURET: the public sample files of the repository, and broken copies.
    measured = os.path.join(repo, "tests", "data", "measured")
    shutil.copy(os.path.join(measured, "abrdf.dat"), os.path.join(folder, "abrdf.dat"))
    shutil.copy(os.path.join(measured, "table.txt"), os.path.join(folder, "table.txt"))
    os.makedirs(os.path.join(folder, "deg"))
    table = open(os.path.join(measured, "table.txt")).read().splitlines()
    write(folder, "deg/table.txt", "\n".join(" ".join([l.split()[0]] + ["%g" % (float(x) * 180 / math.pi) for x in l.split()[1:]])
                                             for l in table) + "\n")
    shutil.copy(os.path.join(measured, "abrdf.dat"), os.path.join(folder, "deg", "abrdf.dat"))
    os.makedirs(os.path.join(folder, "short"))
    shutil.copy(os.path.join(measured, "table.txt"), os.path.join(folder, "short", "table.txt"))
    first = open(os.path.join(measured, "abrdf.dat")).readline().split()
    write(folder, "short/abrdf.dat", " ".join(first[:100]) + "\n")
    # SCATMECH coefficients.
    icobrdf("export", "modes.h5", "--format", "scatmech", "-o", "modes.scatmech.csv")
    text = open(os.path.join(folder, "modes.scatmech.csv")).read()
    write(folder, "nan.scatmech.csv", re.sub(r"\n(1,1,0,0,0,0,0),[^\n]+\n", r"\n\1,nan\n", text, count=1))
    # Nodes that are not files.
    os.makedirs(os.path.join(folder, "folder.h5"))
    os.mkfifo(os.path.join(folder, "fifo.h5"))
    os.mkfifo(os.path.join(folder, "fifo.csv"))
    os.mkfifo(os.path.join(folder, "fifo.toml"))


# ---- the table ---------------------------------------------------------------------------------------------

def table():
    L = "model:lambert:albedo=0.5"
    c = []
    add = c.append
    # Readers: MERL.
    for name, pat in [("empty.binary", "empty|bytes|short"), ("zero-dims.binary", "dim"), ("huge-dims.binary", "dim|bytes|size"),
                      ("short.binary", "bytes|short|truncat"), ("negative-dims.binary", "dim")]:
        add(Case("merl " + name, ["eval", name, "--at", "pair.csv"], code=3, pattern=pat))
    # RGL.
    for name in ["truncated.bsdf", "garbage.bsdf", "header-only.bsdf"]:
        add(Case("rgl " + name, ["eval", name, "--at", "pair.csv"], code=3))
    add(Case("rgl good file read back", ["eval", "ggx.bsdf", "--at", "pair.csv"], expect="ok"))
    # Banks and spectrum files.
    for name in ["truncated.h5", "text.h5", "flipped.h5"]:
        add(Case("bank " + name + " eval", ["eval", name, "--at", "pair.csv"], code=3))
        add(Case("bank " + name + " info", ["bank", "info", name], code=3))
    add(Case("spectrum of a text file", ["spectrum", "text.h5"], code=3))
    add(Case("bank material missing", ["eval", "modes.h5#nope", "--at", "pair.csv"], code=(2, 3), pattern="nope"))
    # CSV samples.
    for name, code in [("empty.csv", 3), ("header.csv", 3), ("nan.csv", 3), ("theta91.csv", 3), ("binary.csv", 3),
                       ("long-line.csv", 3), ("utf16.csv", 3)]:
        add(Case("samples " + name, ["fit", name, "--level", "2", "--order", "2", "-o", "out.h5"], code=code, output="out.h5"))
    add(Case("samples of f = 1e308", ["fit", "huge-f.csv", "--level", "2", "--order", "2", "-o", "out.h5"], code=(3, 4),
             output="out.h5"))
    # Direction pairs.
    add(Case("pairs 1e308 degrees", ["eval", L, "--at", "pairs-1e308.csv"], code=3))
    add(Case("pairs nan", ["eval", L, "--at", "pairs-nan.csv"], code=3))
    add(Case("pairs -0", ["eval", L, "--at", "pairs-minus0.csv"], expect="ok", check=eval_equals(LAMBERT)))
    # Scenes.
    for name, pat in [("empty.toml", "material|bank"), ("binary.toml", ""), ("unclosed.toml", ""), ("level12.toml", "level"),
                      ("order200.toml", "order"), ("target-nan.toml", "target"), ("target-neg.toml", "target"),
                      ("holdout-huge.toml", "holdout"), ("missing-source.toml", "failed|missing"), ("dup.toml", "m")]:
        # A material whose source fails fails the build (exit 4, "bank not written"); the scene itself: exit 3.
        add(Case("scene " + name, ["bank", "build", name, "-o", "out.h5"], code=(3, 4, 5), pattern=pat or None, output="out.h5"))
    add(Case("scene levels = [8] under 1 GB: refused at once", ["--memory-budget", "1G", "bank", "build", "level8.toml", "-o", "out.h5"],
             code=(4, 6), output="out.h5", limit=15))
    # CURET.
    fit = ["--level", "2", "--order", "2", "-o", "out.h5"]
    add(Case("curet sample 999", ["fit", "curet:abrdf.dat#sample=999"] + fit, code=2, pattern="999.*(range|1 to|61)", output="out.h5"))
    add(Case("curet sample -1", ["fit", "curet:abrdf.dat#sample=-1"] + fit, code=2, output="out.h5"))
    add(Case("curet table in degrees", ["fit", "curet:deg/abrdf.dat#sample=1"] + fit, code=3, pattern="degrees", output="out.h5"))
    add(Case("curet short line", ["fit", "curet:short/abrdf.dat#sample=1"] + fit, code=3, output="out.h5"))
    add(Case("curet eval (scattered samples)", ["eval", "curet:abrdf.dat#sample=1", "--at", "pair.csv"], code=(2, 3), pattern="fit them first"))
    add(Case("curet albedo (scattered samples)", ["albedo", "curet:abrdf.dat#sample=1", "--black-sky", "20"], code=(2, 3),
             pattern="fit them first|scattered"))
    add(Case("curet fit", ["fit", "curet:abrdf.dat#sample=1"] + fit, expect="ok", check=output_starts("out.h5", b"\x89HDF")))
    # SCATMECH.
    add(Case("scatmech nan coefficient", ["eval", "scatmech:nan.scatmech.csv", "--at", "pair.csv"], code=3))
    add(Case("scatmech read back", ["eval", "scatmech:modes.scatmech.csv", "--at", "pair.csv"], expect="ok", check=eval_equals(LAMBERT, 1e-9)))
    # Absurd numbers.
    add(Case("albedo=nan", ["eval", "model:lambert:albedo=nan", "--at", "pair.csv"], code=2))
    add(Case("albedo=1e308", ["eval", "model:lambert:albedo=1e308", "--at", "pair.csv"], expect="either", code=(2, 3),
             check=eval_equals(1e308 / math.pi, 1e-12)))
    add(Case("alpha=-0", ["eval", "model:ggx:alpha=-0", "--at", "pair.csv"], code=2))
    add(Case("sample -n 1e18", ["sample", L, "--theta-i", "10", "-n", "1000000000000000000"], code=2))
    add(Case("sample -n 0", ["sample", L, "--theta-i", "10", "-n", "0"], code=2))
    add(Case("sample -n -1", ["sample", L, "--theta-i", "10", "-n", "-1"], code=2))
    add(Case("sample --theta-i nan", ["sample", L, "--theta-i", "nan", "-n", "3"], code=2))
    add(Case("sample three draws", ["sample", L, "--theta-i", "10", "-n", "3"], expect="ok", check=lines_on_stdout(4)))
    add(Case("lut --level 12", ["lut", L, "--level", "12", "-o", "out.h5"], code=(2, 4, 6), output="out.h5"))
    add(Case("fit --order 200", ["fit", L, "--level", "2", "--order", "200", "-o", "out.h5"], code=(2, 4), output="out.h5"))
    add(Case("fit --level 12", ["fit", L, "--level", "12", "--order", "2", "-o", "out.h5"], code=(2, 6), output="out.h5"))
    add(Case("grid --level 12", ["grid", "--level", "12"], code=2))
    add(Case("modes --order 200", ["modes", "--order", "200", "--at", "pair.csv"], code=2))
    add(Case("albedo --black-sky nan", ["albedo", L, "--black-sky", "nan"], code=2))
    add(Case("albedo of Lambert", ["albedo", L, "--black-sky", "20", "--json"], expect="ok", check=albedo_near(0.5, 1e-3)))
    add(Case("plot slice --theta-i 1e308", ["plot", "slice", L, "--theta-i", "1e308", "-o", "out.png"], code=2, output="out.png"))
    add(Case("--memory-budget -0", ["--memory-budget", "-0", "grid", "--level", "1"], code=2))
    add(Case("--memory-budget 1e308", ["--memory-budget", "1e308", "eval", L, "--at", "pair.csv"], expect="either", code=2,
             check=eval_equals(LAMBERT)))
    # Budgets: --memory-budget 1M on each command.
    for args, out in [(["eval", L, "--at", "pair.csv"], None), (["lut", L, "--level", "2", "-o", "out.h5"], "out.h5"),
                      (["fit", L, "--level", "2", "--order", "2", "-o", "out.h5"], "out.h5"), (["albedo", L, "--black-sky", "20"], None),
                      (["sample", L, "--theta-i", "10", "-n", "10"], None), (["plot", "slice", L, "-o", "out.png"], "out.png"),
                      (["export", L, "--format", "rgl", "-o", "out.bsdf"], "out.bsdf"), (["bank", "build", "hybrid.toml", "-o", "out.h5"], "out.h5"),
                      (["bank", "info", "hybrid.h5"], None), (["spectrum", "modes.h5"], None), (["grid", "--level", "4"], None),
                      (["modes", "--order", "8", "--at", "pair.csv"], None), (["smooth", "modes.h5", "-o", "out.h5"], "out.h5"),
                      (["bench", "project", "--level", "3"], None), (["fit", "curet:abrdf.dat#sample=1", "-o", "out.h5"], "out.h5")]:
        add(Case("budget 1M: " + " ".join(args[:2]), ["--memory-budget", "1M"] + args, expect="either", code=(2, 3, 6), output=out))
    # Output side: full disks, closed and full standard output, nodes that are not files.
    add(Case("-o /dev/full", ["lut", L, "--level", "1", "-o", "/dev/full"], code=5))
    add(Case("file size limit 4 kB (a full disk)", ["lut", L, "--level", "3", "--order", "4", "-o", "out.h5"], code=5, output="out.h5",
             fsize=4096))
    add(Case("stdout on /dev/full: eval", ["eval", L, "--at", "pairs.csv"], code=5, stdout="full"))
    add(Case("stdout on /dev/full: sample in blocks", ["sample", L, "--theta-i", "10", "-n", "200000"], code=5, stdout="full"))
    add(Case("stdout closed: spectrum", ["spectrum", "modes.h5"], code=5, stdout="closed"))
    add(Case("stdout closed: grid", ["grid", "--level", "2"], code=5, stdout="closed"))
    add(Case("input is a folder", ["eval", "folder.h5", "--at", "pair.csv"], code=(3, 5)))
    add(Case("input is a FIFO (bank)", ["bank", "info", "fifo.h5"], code=(3, 5), limit=10))
    # A FIFO is read like a file (process substitution, pipes): with no writer the program waits as cat does,
    # and a stop signal ends the wait; a writer of garbage gets a one-line error.
    add(Case("--at is a FIFO, no writer, SIGINT", ["eval", L, "--at", "fifo.csv"], code=130, send=(1.0, signal.SIGINT), limit=10))
    add(Case("--at is a FIFO of garbage", ["eval", L, "--at", "fifo.csv"], code=3, feed=("fifo.csv", bytes(range(256)) * 64), limit=10))
    add(Case("scene is a FIFO, no writer, SIGTERM", ["bank", "build", "fifo.toml", "-o", "out.h5"], code=143, output="out.h5",
             send=(1.0, signal.SIGTERM), limit=10))
    add(Case("scene is a FIFO of garbage", ["bank", "build", "fifo.toml", "-o", "out.h5"], code=3, output="out.h5",
             feed=("fifo.toml", b"[bank\x00\xff"), limit=10))
    add(Case("-o is a folder", ["fit", L, "--level", "1", "--order", "1", "-o", "folder.h5"], code=5))
    # Signals.
    add(Case("SIGINT during sample -n 1e8", ["sample", L, "--theta-i", "10", "-n", "100000000"], code=130,
             send=(1.5, signal.SIGINT), stdout=None))
    add(Case("SIGTERM during bank build", ["bank", "build", "many.toml", "-o", "out.h5"], code=143, output="out.h5",
             send=(0.3, signal.SIGTERM)))
    add(Case("SIGINT during lut level 4", ["lut", "model:ggx:alpha=0.2", "--level", "4", "-o", "out.h5"], code=130, output="out.h5",
             send=(0.5, signal.SIGINT)))
    # Every stored representation through every consumer.
    for ref, rep in [("modes.h5", "modes"), ("lobe.h5#m", "lobe"), ("hybrid.h5#m", "hybrid")]:
        add(Case(rep + ": eval", ["eval", ref, "--at", "pairs.csv"], expect="ok", check=lines_on_stdout(7)))
        add(Case(rep + ": lut", ["lut", ref, "--level", "2", "--order", "2", "-o", "out.h5"], expect="ok",
                 check=output_starts("out.h5", b"\x89HDF")))
        add(Case(rep + ": albedo = sample mean", ["albedo", ref, "--black-sky", "20", "--json"], expect="ok",
                 check=albedo_matches_sample(ref)))
        for kind in ["slice", "sphere", "halfdiff", "curves", "albedo"]:
            add(Case(rep + ": plot " + kind, ["plot", kind, ref, "-o", "out.png"], expect="ok", check=output_starts("out.png", b"\x89PNG")))
        modes_only = rep == "modes"
        add(Case(rep + ": plot spectrum", ["plot", "spectrum", ref, "-o", "out.png"], expect="ok" if modes_only else "fail", code=4,
                 output="out.png", check=output_starts("out.png", b"\x89PNG")))
        add(Case(rep + ": export scatmech", ["export", ref, "--format", "scatmech", "-o", "out.csv"], expect="ok" if modes_only else "fail",
                 code=4, output="out.csv", pattern="Zernike modes only"))
        for fmt, name in [("rgl", "out.bsdf"), ("merl", "out.binary")]:
            add(Case(rep + ": export " + fmt, ["export", ref, "--format", fmt, "-o", name], expect="ok", check=read_back_matches(ref, name)))
        material = ref.split("#")[1] if "#" in ref else "material"  # fit names its one material "material"
        add(Case(rep + ": bank extract", ["bank", "extract", ref.split("#")[0] + "#" + material, "-o", "out.h5"], expect="ok",
                 check=read_back_matches(ref, "out.h5#" + material)))
        add(Case(rep + ": spectrum", ["spectrum", ref], expect="ok"))
        add(Case(rep + ": bank info", ["bank", "info", ref.split("#")[0]], expect="ok"))
        add(Case(rep + ": refit", ["fit", ref, "--level", "2", "--order", "3", "-o", "out.h5"], expect="ok",
                 check=output_starts("out.h5", b"\x89HDF")))
    return c


PROGRAM = None


def eval_at(folder, source, csv="pairs.csv"):
    r = subprocess.run([PROGRAM, "eval", source, "--at", csv], cwd=folder, capture_output=True)
    if r.returncode != 0:
        return None
    return [row[-1] for row in csv_rows(r.stdout)[1]]


def read_back_matches(ref, name):
    def check(r, folder):
        want = eval_at(folder, ref)
        back = eval_at(folder, name)
        if want is None or back is None:
            return "the written file or the bank cannot be evaluated"
        num = sum((a - b) ** 2 for a, b in zip(back, want))
        den = sum(b * b for b in want)
        rel = math.sqrt(num / den) if den > 0 else math.inf
        return None if rel <= READ_BACK_REL else "read back: relative L2 %.3g against eval of the bank" % rel
    return check


def albedo_matches_sample(ref):
    def check(r, folder):
        got = json.loads(r["out"])["black_sky"][0]["albedo"][0]
        s = subprocess.run([PROGRAM, "sample", ref, "--theta-i", "20", "-n", "20000", "--seed", "5"], cwd=folder, capture_output=True)
        if s.returncode != 0:
            return "sample failed: " + s.stderr.decode()[:200]
        w = [row[3] for row in csv_rows(s.stdout)[1]]
        mean = sum(w) / len(w)
        sd = math.sqrt(max(0.0, sum(x * x for x in w) / len(w) - mean * mean))
        tol = SAMPLE_SIGMAS * sd / math.sqrt(len(w)) + 2e-3 * abs(got)  # plus the albedo's quadrature error
        return None if abs(mean - got) <= tol else "albedo %.5g, mean sample weight %.5g (tolerance %.2g)" % (got, mean, tol)
    return check


def main():
    global PROGRAM
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--program", default=os.path.join(repo, "build", "cli", "icobrdf"))
    ap.add_argument("--only", default="")
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()
    PROGRAM = os.path.abspath(a.program)
    base = tempfile.mkdtemp(prefix="icobrdf-adversarial-")
    fixtures = os.path.join(base, "fixtures")
    os.makedirs(fixtures)
    make_fixtures(PROGRAM, fixtures, repo)
    counts = {"OK": 0, "weak": 0, "bad": 0}
    cases = [c for c in table() if a.only in c.name]
    for k, case in enumerate(cases):
        folder = os.path.join(base, "case-%03d" % k)
        shutil.copytree(fixtures, folder, symlinks=True, ignore=lambda d, names: [n for n in names if n.startswith("fifo")])
        for n in ["fifo.h5", "fifo.csv", "fifo.toml"]:
            os.mkfifo(os.path.join(folder, n))
        r = run(PROGRAM, case, folder)
        verdict, why = classify(case, r, folder)
        counts[verdict] += 1
        if verdict != "OK" or a.verbose:
            print("%-5s %-52s %5.1f s  %s" % (verdict, case.name[:52], r["seconds"], why[:240]))
        shutil.rmtree(folder, ignore_errors=True)
    shutil.rmtree(base, ignore_errors=True)
    print("%d cases: %d OK, %d weak, %d bad (%s)" % (len(cases), counts["OK"], counts["weak"], counts["bad"],
                                                     time.strftime("%Y-%m-%d")))
    return min(counts["bad"], 100)


if __name__ == "__main__":
    sys.exit(main())
