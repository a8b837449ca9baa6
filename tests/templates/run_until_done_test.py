"""jobs/templates/run_until_done.sh under mpirun, stopped as a user at a terminal stops it.

A Ctrl-C (SIGINT to the script) makes the solve write its checkpoint and the script exit 75
without starting again; running the script again resumes from the checkpoint and finishes; two
Ctrl-Cs end it at once. Usage: run_until_done_test.py RADIOSITY SOURCE_DIR
"""
import os
import signal
import subprocess
import sys
import tempfile
import time

radiosity, source = sys.argv[1], sys.argv[2]
script = os.path.join(source, "jobs", "templates", "run_until_done.sh")
failures = []
checks = 0


def check(condition, what):
    global checks
    checks += 1
    print(("ok: " if condition else "FAIL: ") + what)
    if not condition:
        failures.append(what)


def start(folder, job):
    env = dict(os.environ, RADIOSITY=radiosity, NP="2", CHECKPOINT_EVERY="0",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    log = open(os.path.join(folder, "log.txt"), "a")
    return subprocess.Popen(["bash", script, job], cwd=folder, env=env, stdout=log,
                            stderr=subprocess.STDOUT)


def log_size(folder):
    path = os.path.join(folder, "log.txt")
    return os.path.getsize(path) if os.path.exists(path) else 0


def wait_for(folder, text, seconds, since):
    """Until the log holds `text` after byte `since` (this run's solve is under way: the log is
    appended to, and an earlier run's line must not count, or the Ctrl-C comes before mpirun
    handles signals and SIGUSR1 kills it)."""
    end = time.time() + seconds
    while time.time() < end:
        with open(os.path.join(folder, "log.txt")) as log:
            log.seek(since)
            if text in log.read():
                return True
        time.sleep(0.1)
    return False


with tempfile.TemporaryDirectory() as folder:
    job = os.path.join(folder, "job.toml")
    with open(job, "w") as f:
        # Long enough to be stopped in the middle of its form factors on any machine.
        f.write('scene = "builtin:rooms?patches=20000"\noutput = "rooms.h5"\nrays = 4096\n'
                'estimator = "hemisphere"\n')
    checkpoint = os.path.join(folder, "job.checkpoint.h5")

    since = log_size(folder)
    run = start(folder, job)
    check(wait_for(folder, "form factors:", 120, since), "the solve started")
    time.sleep(1)
    run.send_signal(signal.SIGINT)
    code = run.wait(timeout=300)
    check(code == 75, "one Ctrl-C: exit 75 (was %d)" % code)
    check(os.path.exists(checkpoint), "one Ctrl-C: the checkpoint is written")
    check(not os.path.exists(os.path.join(folder, "rooms.h5")), "one Ctrl-C: no result yet")
    with open(os.path.join(folder, "log.txt")) as log:
        text = log.read()
    check("restarting" not in text, "one Ctrl-C: not started again")

    run = start(folder, job)
    code = run.wait(timeout=600)
    check(code == 0, "run again: exit 0 (was %d)" % code)
    with open(os.path.join(folder, "log.txt")) as log:
        check("restart: " in log.read(), "run again: resumed from the checkpoint")
    check(os.path.exists(os.path.join(folder, "rooms.h5")), "run again: the result is written")

    os.remove(checkpoint)
    since = log_size(folder)
    run = start(folder, job)
    check(wait_for(folder, "form factors:", 120, since), "third run started")
    run.send_signal(signal.SIGINT)
    time.sleep(0.2)
    run.send_signal(signal.SIGINT)
    code = run.wait(timeout=60)
    # (bash ends through SIGINT itself when its INT trap exits, as a shell's Ctrl-C should)
    check(code in (130, -signal.SIGINT), "two Ctrl-Cs: ended at once (exit %d)" % code)
    time.sleep(3)
    left = subprocess.run(["pgrep", "-f", "solve --config " + job], capture_output=True, text=True)
    check(left.stdout.strip() == "", "two Ctrl-Cs: no rank left running")

print("%d passed, %d failed" % (checks - len(failures), len(failures)))
sys.exit(1 if failures else 0)
