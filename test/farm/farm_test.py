#!/usr/bin/python3
"""osl-farm with real processes on this machine: a Dask scheduler and two
workers on free ports. A grid in 16 tiles equals one osl-run's images bit
for bit (float EXR, int TIFF, -od uint8), a scene in 16 tiles one osl-run
--scene's; killing a worker mid-job still
gives the identical image; a shader error and a tile failing where it runs
fail the job with osl-run's message and leave no file; `suite` runs a
folder's shaders as tasks.

  farm_test.py --bin BUILD/bin
"""
import argparse
import filecmp
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    def __init__(self, tmp):
        self.procs = []
        port = free_port()
        self.address = "tcp://127.0.0.1:%d" % port
        self.procs.append(self.start(["dask-scheduler", "--host", "127.0.0.1", "--port",
                                      str(port), "--no-dashboard"], tmp, "scheduler"))
        self.workers = [self.start(["dask-worker", self.address, "--nthreads", "1",
                                    "--nworkers", "1", "--no-dashboard", "--name", "w%d" % i,
                                    "--death-timeout", "60"], tmp, "worker%d" % i)
                        for i in range(2)]
        self.procs += self.workers
        from dask.distributed import Client
        with Client(self.address, timeout=60) as client:
            client.wait_for_workers(2, timeout=60)

    def start(self, cmd, tmp, name):
        log = open(os.path.join(tmp, name + ".log"), "w")
        return subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)

    def stop(self):
        for p in self.procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
            p.wait()


def check(condition, message):
    if not condition:
        print("FAIL: " + message)
        sys.exit(1)
    print("ok: " + message)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    a = ap.parse_args()
    osl_run = os.path.join(a.bin, "osl-run")
    farm = os.path.join(a.bin, "osl-farm")
    imgdiff = os.path.join(a.bin, "osl-imgdiff")
    shader = os.path.join(HERE, "tiles.osl")
    tmp = tempfile.mkdtemp(prefix="osl-farm-test-")
    cache = os.path.join(tmp, "cache")
    grid = ["-g", "160", "96"]

    def same(a_path, b_path):
        return subprocess.run([imgdiff, a_path, b_path], capture_output=True).returncode == 0

    subprocess.run([osl_run, shader] + grid + ["-o", "c", os.path.join(tmp, "ref.exr"),
                    "-o", "k", os.path.join(tmp, "ref.tif")], check=True, capture_output=True)
    subprocess.run([osl_run, shader] + grid + ["-od", "uint8", "-o", "c",
                    os.path.join(tmp, "ref8.tif")], check=True, capture_output=True)
    cluster = Cluster(tmp)
    try:
        common = [farm, "shade", shader] + grid + ["--scheduler", cluster.address,
                                                    "--cache-dir", cache]
        r = subprocess.run(common + ["--tiles", "16", "-o", "c", os.path.join(tmp, "c.exr"),
                                     "-o", "k", os.path.join(tmp, "k.tif")],
                           capture_output=True, text=True)
        check(r.returncode == 0, "16 tiles shade (%s)" % r.stderr.strip()[-300:])
        check(same(os.path.join(tmp, "ref.exr"), os.path.join(tmp, "c.exr")),
              "the assembled color output equals one osl-run's")
        check(filecmp.cmp(os.path.join(tmp, "ref.tif"), os.path.join(tmp, "k.tif"),
                          shallow=False), "the int output's TIFF is the same file")
        r = subprocess.run(common + ["--tiles", "7", "-o", "c", os.path.join(tmp, "c8.tif"),
                                     "--", "-od", "uint8"], capture_output=True, text=True)
        check(r.returncode == 0 and filecmp.cmp(os.path.join(tmp, "ref8.tif"),
                                                os.path.join(tmp, "c8.tif"), shallow=False),
              "-od uint8 over 7 uneven tiles gives the same file")

        scene = os.path.join(os.path.dirname(os.path.dirname(HERE)), "render", "scenes",
                             "glass.xml")
        render = ["-r", "48", "32", "-aa", "2"]
        subprocess.run([osl_run, "--scene", scene] + render + ["-o", os.path.join(
            tmp, "scene_ref.exr")], check=True, capture_output=True)
        r = subprocess.run([farm, "render", scene] + render +
                           ["--tiles", "16", "--scheduler", cluster.address, "--cache-dir",
                            cache, "-o", os.path.join(tmp, "scene.exr")],
                           capture_output=True, text=True)
        check(r.returncode == 0 and same(os.path.join(tmp, "scene_ref.exr"),
                                         os.path.join(tmp, "scene.exr")),
              "a scene rendered in 16 tiles equals one osl-run --scene (%s)" %
              r.stderr.strip()[-200:])

        # A worker killed once the job is under way: its tiles run elsewhere.
        # About 15 s of shading in all, so that tiles last.
        big = ["-g", "640", "480"]
        slow = ["--tiles", "24", "--progress", "-o", "c", os.path.join(tmp, "killed.exr"),
                "--", "--param", "iterations", "20000"]
        subprocess.run([osl_run, shader] + big + ["--param", "iterations", "20000", "-o", "c",
                        os.path.join(tmp, "ref_slow.exr")], check=True, capture_output=True)
        job = subprocess.Popen(common[:3] + big + common[6:] + slow, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
        progress = ""
        while "farm: 1/" not in progress and job.poll() is None:
            progress += job.stderr.read(1)
        # Killed while it runs a tile: an osl-run in its session.
        victim = cluster.workers[0]
        deadline = time.time() + 60
        while job.poll() is None and time.time() < deadline and subprocess.run(
                ["pgrep", "-s", str(victim.pid), "osl-run"], capture_output=True).returncode:
            time.sleep(0.005)
        busy = job.poll() is None and time.time() < deadline
        os.killpg(victim.pid, signal.SIGKILL)
        out, err = job.communicate(timeout=600)
        last = (progress + err).strip().replace("\r", "\n").splitlines()[-1:]
        check(busy, "a worker is killed in the middle of a tile (%s)" % " ".join(last))
        check(job.returncode == 0, "the job survives it (%s)" % " ".join(last))
        check(same(os.path.join(tmp, "ref_slow.exr"), os.path.join(tmp, "killed.exr")),
              "and its image equals one osl-run's")

        bad = os.path.join(HERE, "bad.osl")
        r = subprocess.run([farm, "shade", bad, "-g", "8", "8", "--scheduler", cluster.address,
                            "-o", "f", os.path.join(tmp, "bad.exr")],
                           capture_output=True, text=True)
        check(r.returncode != 0 and "bad.osl:4:" in r.stderr and
              not os.path.exists(os.path.join(tmp, "bad.exr")),
              "a shader error fails the job with its file:line (%s)" % r.stderr.strip()[-200:])
        missing = os.path.join(HERE, "missing_texture.osl")
        r = subprocess.run([farm, "shade", missing, "-g", "8", "8", "--scheduler",
                            cluster.address, "--tiles", "4", "-o", "c",
                            os.path.join(tmp, "missing.exr")], capture_output=True, text=True)
        check(r.returncode != 0 and "no-such-texture.tx" in r.stderr and
              not os.path.exists(os.path.join(tmp, "missing.exr")),
              "a tile failing where it runs fails the job (%s)" % r.stderr.strip()[-200:])

        folder = os.path.join(tmp, "shaders")
        os.makedirs(folder)
        for name in ("tiles.osl", "bad.osl"):
            shutil.copy(os.path.join(HERE, name), folder)
        r = subprocess.run([farm, "suite", folder, "--scheduler", cluster.address],
                           capture_output=True, text=True)
        check(r.returncode == 1 and "PASS: tiles.osl" in r.stdout and
              "FAIL: bad.osl - " in r.stdout and "1 passed, 1 failed" in r.stdout,
              "a folder's shaders run as tasks, each judged (%s)" % r.stdout.strip()[-200:])
    finally:
        cluster.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
