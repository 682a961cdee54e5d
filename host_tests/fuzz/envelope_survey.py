#!/usr/bin/env python3
"""M303 over issue 7's hotend envelope: runs autotune_fuzz's envelope mode (AUTOTUNE_FUZZ_ENVELOPE=1)
on a uniform random draw and on a grid of its hard corner (strong heaters behind long sensor lags),
and prints how many tunes pass and how the others fail.

  host_tests/fuzz/envelope_survey.py [--fuzzer build/host_tests/fuzz/autotune_fuzz]
                                     [--sample N] [--seeds 1,2] [--grid] [--list-failures]

--sample N draws N hotends per seed (the byte layout is autotune_fuzz.cpp's envelope_hotend_from);
--grid adds K 700–1,300 °C × τ1 60–300 s × lag + delay 10–25 s (no delay or 15 % of it) × σ 0.05 /
0.25 °C × two targets, C5 F1 (448 hotends). Each input runs in its own process (the fuzzer binary
aborts on an oracle). Plain Python 3, no packages; two processes at a time."""
import argparse
import collections
import concurrent.futures
import itertools
import math
import os
import random
import re
import subprocess
import tempfile

OUTCOME = re.compile(r"seconds (\d+) max-S ([-\d.]+)")


def run_one(fuzzer, data):
    with tempfile.NamedTemporaryFile(delete=False) as f:
        f.write(data)
        path = f.name
    try:
        env = dict(os.environ, AUTOTUNE_FUZZ_STATS="1", AUTOTUNE_FUZZ_ENVELOPE="1")
        r = subprocess.run([fuzzer, path], env=env, capture_output=True, text=True)
    finally:
        os.unlink(path)
    lines = r.stderr.splitlines()
    outcome = next((l for l in lines if l.startswith("outcome")), None)
    if outcome is None:
        return None  # outside the envelope (the harness returns before tuning)
    oracle = next((l[len("oracle: "):] for l in lines if l.startswith("oracle")), "ok")
    kind = "ok"
    if oracle != "ok":
        kind = "above S + 5 °C" if "above S + 5" in oracle else (
            "S + 25 °C abort" if "failure 2" in outcome else (
                "relay did not oscillate" if "failure 5" in outcome else oracle.split(" (")[0]))
    seconds, max_s = OUTCOME.search(outcome).groups()
    return kind, int(seconds), float(max_s), outcome.split(" | ")[1], data.hex()


def byte_for(v, lo, hi):
    return max(0, min(255, round(255 * (v - lo) / (hi - lo))))


def grid_inputs():
    for k, t1, total, share, sigma, s_byte in itertools.product(
            [700, 900, 1100, 1300], [60, 100, 150, 300], [10, 15, 20, 25], [0, 0.15], [0.05, 0.25], [255, 128]):
        if k / t1 > 16:
            continue  # beyond the envelope's 16 °C/s
        b = [byte_for(k, 300, 1300), round(255 * math.log2(t1 / 30) / 3.32), round(255 * share),
             byte_for(total, 1, 25), 100, round(255 * sigma / 0.3), 40, 128, 0, s_byte, 2, 0, 7]
        yield bytes(max(0, min(255, x)) for x in b)


def sample_inputs(n, seed):
    rng = random.Random(seed)
    while True:  # as many as needed: the caller keeps the first n inside the envelope
        yield bytes(rng.randrange(256) for _ in range(13))


def survey(fuzzer, inputs, n=None):
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        it = iter(inputs)
        while n is None or len(results) < n:
            batch = list(itertools.islice(it, 16))
            if not batch:
                break
            for r in pool.map(lambda d: run_one(fuzzer, d), batch):
                if r is not None and (n is None or len(results) < n):
                    results.append(r)
    return results


def report(name, results, list_failures):
    kinds = collections.Counter(r[0] for r in results)
    ok = [r for r in results if r[0] == "ok"]
    durations = sorted(r[1] for r in ok)
    print(f"| {name} | {len(results)} | {len(ok)} ({100.0 * len(ok) / max(1, len(results)):.1f} %) | "
          + ", ".join(f"{k} {v}" for k, v in sorted(kinds.items()) if k != "ok") + " | "
          + (f"{max(r[2] for r in ok):.2f} | {durations[len(durations) // 2]}" if ok else "– | –") + " |")
    if list_failures:
        for r in results:
            if r[0] != "ok":
                print(f"    {r[0]}: {r[1]} s, max − S {r[2]:+.2f} °C | {r[3]} | {r[4]}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fuzzer", default="build/host_tests/fuzz/autotune_fuzz")
    ap.add_argument("--sample", type=int, default=300)
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--grid", action="store_true")
    ap.add_argument("--list-failures", action="store_true")
    a = ap.parse_args()
    print("| set | hotends | pass | failures | worst max − S of the passes (°C) | median tune (s) |")
    print("|---|---|---|---|---|---|")
    for seed in [int(s) for s in a.seeds.split(",") if s] if a.sample > 0 else []:
        report(f"uniform, seed {seed}", survey(a.fuzzer, sample_inputs(a.sample, seed), a.sample), a.list_failures)
    if a.grid:
        report("grid: strong heater, long lag", survey(a.fuzzer, grid_inputs()), a.list_failures)


if __name__ == "__main__":
    main()
