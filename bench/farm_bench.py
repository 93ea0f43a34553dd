#!/usr/bin/python3
"""osl-farm's throughput on this machine: one Dask worker against two (one
thread each, one osl-run thread per tile), and the overhead of a tile
(process start and a warm kernel cache: a 1x1 --crop).

  bench/farm_bench.py --bin build/bin [--shader shaders/marble.osl] [-g 1024 1024]
                      [--tiles 16] [--repeat 3]

Times are medians of --repeat runs, measured in one run of this script;
compare the ratios, not the seconds, across machines.
"""
import argparse
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cluster(workers, tmp):
    port = free_port()
    address = "tcp://127.0.0.1:%d" % port
    log = open(os.path.join(tmp, "cluster.log"), "a")
    procs = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--no-dashboard"], stdout=log, stderr=log,
                              start_new_session=True)]
    procs += [subprocess.Popen(["dask-worker", address, "--nthreads", "1", "--no-dashboard"],
                               stdout=log, stderr=log, start_new_session=True)
              for _ in range(workers)]
    from dask.distributed import Client
    with Client(address, timeout=60) as c:
        c.wait_for_workers(workers, timeout=60)
    return address, procs


def stop(procs):
    for p in procs:
        os.killpg(p.pid, signal.SIGKILL)
        p.wait()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--shader", default=os.path.join(ROOT, "shaders", "marble.osl"))
    ap.add_argument("-g", nargs=2, type=int, default=[1024, 1024])
    ap.add_argument("--tiles", type=int, default=16)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    farm, osl_run = os.path.join(a.bin, "osl-farm"), os.path.join(a.bin, "osl-run")
    tmp = tempfile.mkdtemp(prefix="osl-farm-bench-")
    cache = os.path.join(tmp, "cache")
    out_name = subprocess.run([osl_run, "--info", a.shader], capture_output=True, text=True,
                              check=True).stdout
    output = out_name.split('"output')[0].split('"')[-2]
    grid = ["-g", str(a.g[0]), str(a.g[1])]
    times = {}
    for workers in (1, 2):
        address, procs = cluster(workers, tmp)
        try:
            runs = []
            for _ in range(a.repeat + 1):  # the first warms the kernel cache
                start = time.perf_counter()
                subprocess.run([farm, "shade", a.shader] + grid +
                               ["--tiles", str(a.tiles), "--scheduler", address, "--cache-dir",
                                cache, "-o", output, os.path.join(tmp, "out.exr"), "--", "-t",
                                "1"], check=True, capture_output=True)
                runs.append(time.perf_counter() - start)
            times[workers] = statistics.median(runs[1:])
        finally:
            stop(procs)
    tile = []
    for _ in range(a.repeat + 1):
        start = time.perf_counter()
        subprocess.run([osl_run, a.shader] + grid + ["--crop", "0", "0", "1", "1", "-t", "1",
                        "--cache-dir", cache, "-o", output, os.path.join(tmp, "t.exr")],
                       check=True, capture_output=True)
        tile.append(time.perf_counter() - start)
    single = []
    for _ in range(a.repeat):
        start = time.perf_counter()
        subprocess.run([osl_run, a.shader] + grid + ["-t", "1", "--cache-dir", cache, "-o",
                        output, os.path.join(tmp, "one.exr")], check=True, capture_output=True)
        single.append(time.perf_counter() - start)
    print("%s, %dx%d grid, %d tiles (medians of %d)" % (os.path.basename(a.shader), a.g[0],
                                                        a.g[1], a.tiles, a.repeat))
    print("  one osl-run, one thread:     %.3f s" % statistics.median(single))
    print("  osl-farm, 1 worker:          %.3f s" % times[1])
    print("  osl-farm, 2 workers:         %.3f s  (%.2fx of 1 worker's throughput)" %
          (times[2], times[1] / times[2]))
    print("  a tile's overhead (1x1 crop, warm cache): %.3f s" % statistics.median(tile[1:]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
