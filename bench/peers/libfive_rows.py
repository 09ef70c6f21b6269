#!/usr/bin/python3
"""fortu beside libfive, interleaved: the rows of the 2D/3D evaluation, meshing and
shaded-view comparisons, run by bench/peers.sh (which builds the libfive drivers).

Why interleaved separate processes: the machine is shared and its load changes by the
minute, so every case of a row group runs once per round (rotating the starting case),
each as its own process under `/usr/bin/time -v taskset -c CPUS` (the conventions of
../shared/peers/ilv.py); medians over the rounds are compared, as are max RSS figures.

What each time covers (the tools' own timers; parsing, compiling, optimising the tree,
building evaluators and writing output are excluded on both sides):
  fortu grid rows   `evaluate` of `fortu run --stats` (points / the printed speed, so finer
                    than its 1 ms print), the engine filling the whole grid;
  fortu mesh rows   `mesh` of `--stats`: octree, vertices, sharp features, the mesh in memory;
  fortu view rows   `render` of `--stats`: the shaded picture in memory (not the PNG write);
  libfive           eval_ms of the driver's RESULT line: steady clock around the one render
                    call (ArrayEvaluator loop, interval quad/octree, Mesh::render,
                    Heightmap::render).

floz64.vm runs on libfive_vm_noopt (libfive's Deck without Tree::optimized(), which does not
finish on this 64-deep R0 fold in minutes); every other row on stock libfive.

Usage: libfive_rows.py --fortu BIN --lf-vm EXE --lf-vm-noopt EXE --lf-mesh EXE --data DIR --floz FILE
                       --out DIR [--rows a,b] [--threads 1,2] [--repeat N] [--slow-repeat N]
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import time

CPUS = {1: "0", 2: "0,1"}


# --- the rows: one list everything (the run, the CSV, the table) comes from --------------
# (id, group, what, slow, fortu case, [libfive cases]); a case is (label, argv builder).
# The argv builders take the threads count and return the command without time/taskset.
def rows(a, work):
    d = lambda f: os.path.join(a.data, f)
    prospero, bear, tangle = d("prospero.vm"), d("bear.vm"), d("tanglecube.vm")

    def fortu_grid(model, n, mode):
        extra = {"f32": ["--precision", "float32"], "f64": [], "sign": ["--sign-only"]}[mode]
        return lambda t: [a.fortu, "run", model, "--size", str(n), "--threads", str(t),
                          "--stats"] + extra

    def fortu_mesh(model, cells):
        out = os.path.join(work, "fortu_%s_%d.stl" % (os.path.basename(model), cells))
        return lambda t: [a.fortu, "run", model, "--size", str(cells + 1), "--threads", str(t),
                          "-o", out, "--stats"]

    def fortu_view(model, n):
        out = os.path.join(work, "fortu_view_%d.png" % n)
        return lambda t: [a.fortu, "run", model, "--size", str(n), "--view", "front",
                          "--threads", str(t), "-o", out, "--stats"]

    def lf_vm(model, n, mode, exe=None):
        return lambda t: [exe or a.lf_vm, model, str(n), "--mode", mode, "--threads", str(t)]

    def lf_mesh(model, cells, heightmap=False):
        return lambda t: [a.lf_mesh, model, str(cells), "--threads", str(t)] + \
            (["--heightmap"] if heightmap else [])

    R = []
    def row(rid, group, what, slow, fortu, peers):
        R.append(dict(id=rid, group=group, what=what, slow=slow, fortu=fortu, peers=peers))

    row("prospero-sign", "prospero-sign", "prospero.vm 1024² sign image", False,
        ("fortu sign", fortu_grid(prospero, 1024, "sign")),
        [("libfive quadtree", lf_vm(prospero, 1024, "quadtree")),
         ("libfive heightmap", lf_vm(prospero, 1024, "heightmap"))])
    row("prospero-f32", "prospero-field", "prospero.vm 1024² full field, float32", False,
        ("fortu float32", fortu_grid(prospero, 1024, "f32")),
        [("libfive brute force", lf_vm(prospero, 1024, "brute"))])
    row("prospero-f64", "prospero-field", "prospero.vm 1024² full field, float64 (libfive float32)", False,
        ("fortu float64", fortu_grid(prospero, 1024, "f64")),
        [("libfive brute force", lf_vm(prospero, 1024, "brute"))])
    row("floz-sign", "floz", "floz64.vm 800² sign image", False,
        ("fortu sign", fortu_grid(a.floz, 800, "sign")),
        [("libfive quadtree, no optimiser", lf_vm(a.floz, 800, "quadtree", a.lf_vm_noopt))])
    row("floz-f32", "floz", "floz64.vm 800² full field, float32", False,
        ("fortu float32", fortu_grid(a.floz, 800, "f32")),
        [("libfive brute force, no optimiser", lf_vm(a.floz, 800, "brute", a.lf_vm_noopt))])
    row("bear128-f32", "bear128", "bear.vm 128³ full field, float32", False,
        ("fortu float32", fortu_grid(bear, 128, "f32")),
        [("libfive brute force", lf_vm(bear, 128, "brute"))])
    row("bear256-f32", "bear256", "bear.vm 256³ full field, float32", True,
        ("fortu float32", fortu_grid(bear, 256, "f32")),
        [("libfive brute force", lf_vm(bear, 256, "brute"))])
    row("bear256-sign", "bear256", "bear.vm 256³ sign volume", True,
        ("fortu sign", fortu_grid(bear, 256, "sign")),
        [("libfive octree", lf_vm(bear, 256, "quadtree"))])
    row("tangle256-sign", "tangle256", "tanglecube.vm 256³ sign volume", False,
        ("fortu sign", fortu_grid(tangle, 256, "sign")),
        [("libfive octree", lf_vm(tangle, 256, "quadtree"))])
    for model, name in ((tangle, "tangle"), (bear, "bear")):
        for cells in (256, 512):
            row("mesh-%s%d" % (name, cells), "mesh-%s%d" % (name, cells),
                "mesh %s, %d cells per axis" % (os.path.basename(model), cells), True,
                ("fortu -o m.stl", fortu_mesh(model, cells)),
                [("libfive Mesh::render", lf_mesh(model, cells))])
    row("view-bear1024", "view-bear1024", "bear.vm 1024² shaded view (1024 depth samples)", True,
        ("fortu -o v.png --view front", fortu_view(bear, 1024)),
        [("libfive Heightmap::render", lf_mesh(bear, 1024, heightmap=True))])
    return R


# --- one process --------------------------------------------------------------------------
def parse_fortu(text):
    """The time fortu's --stats gives for what the run made, its own peak, and a count."""
    out = {}
    m = re.search(r"speed: ([0-9,]+) points/s", text)
    v = re.search(r"inside (\d+), boundary (\d+), outside (\d+), invalid (\d+)", text)
    if m and v and int(m.group(1).replace(",", "")) > 0:
        points = sum(int(g) for g in v.groups())
        out["ms"] = points / int(m.group(1).replace(",", "")) * 1000
        out["count"] = "inside=%s" % v.group(1)
    for key in ("evaluate", "mesh", "render"):
        m = re.search(r"time:.*\b%s ([0-9.]+) s" % key, text)
        if m and "ms" not in out:
            out["ms"] = float(m.group(1)) * 1000
    m = re.search(r"mesh: (\d+) triangles", text)
    if m:
        out["count"] = "triangles=%s" % m.group(1)
    m = re.search(r"peak memory: ([0-9.]+) MiB", text)
    out["own_mib"] = m.group(1) if m else ""
    return out


def parse_result(text):
    line = [l for l in text.splitlines() if l.startswith("RESULT")][-1]
    kv = dict(t.split("=", 1) for t in line.split()[1:] if "=" in t)
    count = next((k + "=" + kv[k] for k in ("triangles", "inside", "filled") if k in kv), "")
    return {"ms": float(kv["eval_ms"]), "count": count, "own_mib": ""}


def run_one(argv, threads, kind):
    full = ["/usr/bin/time", "-v", "taskset", "-c", CPUS[threads]] + argv
    t0 = time.perf_counter()
    p = subprocess.run(full, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError("failed (%d): %s\n%s%s" % (p.returncode, " ".join(full),
                                                     p.stdout[-2000:], p.stderr[-2000:]))
    r = (parse_fortu if kind == "fortu" else parse_result)(p.stdout + p.stderr)
    if "ms" not in r:
        raise RuntimeError("no time in the output of %s:\n%s" % (" ".join(full), p.stdout + p.stderr))
    r["rss_mib"] = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1)) / 1024
    # CPU seconds of the whole process (user + system): on a machine loaded far beyond its
    # cores a run waits most of its wall time, and the CPU it used is the steadier figure.
    r["cpu_s"] = sum(float(re.search(r"%s time \(seconds\): ([0-9.]+)" % k, p.stderr).group(1))
                     for k in ("User", "System"))
    r["wall_s"] = wall
    r["command"] = " ".join(full)
    return r


def load():
    return open("/proc/loadavg").read().split()[0]


# --- a group: its cases, interleaved --------------------------------------------------------
def run_group(group_rows, threads_list, repeat, writer, fh):
    cases = {}   # (label, threads) -> case; libfive cases shared by two rows run once
    for r in group_rows:
        for t in threads_list:
            for kind, (label, make) in [("fortu", r["fortu"])] + [("libfive", p) for p in r["peers"]]:
                argv = make(t)
                key = tuple(argv)
                if key not in cases:
                    cases[key] = dict(label=label, threads=t, kind=kind, argv=argv, runs=[])
    order = list(cases.values())
    for rnd in range(repeat):
        for pos in range(len(order)):
            c = order[(rnd + pos) % len(order)]
            before = load()
            r = run_one(c["argv"], c["threads"], c["kind"])
            c["runs"].append(r)
            writer.writerow([group_rows[0]["group"], c["label"], c["threads"], rnd, pos,
                             "%.3f" % r["ms"], "%.1f" % r["rss_mib"], r["own_mib"],
                             "%.3f" % r["wall_s"], "%.2f" % r["cpu_s"], before, r.get("count", ""), r["command"]])
            fh.flush()
            print("  round %d  %-28s %dt  %10.2f ms  cpu %7.2f s  rss %7.1f MiB  load %s"
                  % (rnd, c["label"], c["threads"], r["ms"], r["cpu_s"], r["rss_mib"], before), flush=True)
    return cases


def fmt_ms(v):
    return "%.0f ms" % v if v >= 100 else "%.1f ms" % v if v >= 10 else "%.2f ms" % v


def main():
    ap = argparse.ArgumentParser()
    for k in ("fortu", "lf_vm", "lf_vm_noopt", "lf_mesh", "data", "floz", "out"):
        ap.add_argument("--" + k.replace("_", "-"), required=True)
    ap.add_argument("--rows", default="all")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--slow-repeat", type=int, default=3)
    ap.add_argument("--work", default="/tmp")
    a = ap.parse_args()
    every = rows(a, a.work)
    if a.rows == "list":
        for r in every:
            print("%-16s %s%s" % (r["id"], r["what"], "  (slow)" if r["slow"] else ""))
        return 0
    wanted = [r["id"] for r in every] if a.rows == "all" else a.rows.split(",")
    unknown = [w for w in wanted if w not in {r["id"] for r in every}]
    if unknown:
        print("libfive_rows.py: unknown row(s) %s (--rows list shows them)" % ",".join(unknown), file=sys.stderr)
        return 2
    threads_list = [int(t) for t in a.threads.split(",")]
    if any(t not in CPUS for t in threads_list):
        print("libfive_rows.py: --threads takes 1 and/or 2", file=sys.stderr)
        return 2
    chosen = [r for r in every if r["id"] in wanted]
    os.makedirs(a.out, exist_ok=True)
    stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    table = []
    with open(os.path.join(a.out, "runs.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["group", "case", "threads", "round", "position", "ms", "max_rss_mib",
                    "fortu_own_peak_mib", "process_wall_s", "process_cpu_s", "load_before", "count",
                    "command"])
        groups = []
        for r in chosen:
            if r["group"] not in groups:
                groups.append(r["group"])
        for g in groups:
            members = [r for r in chosen if r["group"] == g]
            repeat = a.slow_repeat if any(r["slow"] for r in members) else a.repeat
            print("%s: %d rounds, load %s" % (g, repeat, load()), flush=True)
            cases = run_group(members, threads_list, repeat, w, fh)
            for r in members:
                for t in threads_list:
                    f = cases[tuple(r["fortu"][1](t))]
                    for label, make in r["peers"]:
                        table.append((r, t, f, label, cases[tuple(make(t))]))
    med = lambda c, k="ms": statistics.median(x[k] for x in c["runs"])
    lines = ["# fortu beside libfive (%s, load average %s at the end)" % (stamp, load()), "",
             "Medians of interleaved runs (min–max) of the tools' own timers; ratio = fortu median / "
             "libfive median; CPU = user + system seconds of the whole process (setup included), "
             "median; max RSS of the process.", "",
             "| work | threads | fortu | libfive | fortu : libfive | CPU fortu / libfive (ratio) | fortu max RSS | libfive max RSS | runs |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r, t, f, label, p in table:
        fm, pm = med(f), med(p)
        fc, pc = med(f, "cpu_s"), med(p, "cpu_s")
        cpu = "%.2f / %.2f s (%.2f)" % (fc, pc, fc / pc if pc > 0 else float("nan"))
        lines.append("| %s | %d | %s (%s–%s) | %s %s (%s–%s) | %.2f | %s | %.1f MiB | %.1f MiB | %d |" % (
            r["what"], t, fmt_ms(fm), fmt_ms(min(x["ms"] for x in f["runs"])),
            fmt_ms(max(x["ms"] for x in f["runs"])), label, fmt_ms(pm),
            fmt_ms(min(x["ms"] for x in p["runs"])), fmt_ms(max(x["ms"] for x in p["runs"])),
            fm / pm, cpu, max(x["rss_mib"] for x in f["runs"]), max(x["rss_mib"] for x in p["runs"]),
            len(f["runs"])))
    text = "\n".join(lines) + "\n"
    open(os.path.join(a.out, "table.md"), "w").write(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
