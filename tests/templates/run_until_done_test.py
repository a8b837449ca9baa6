"""jobs/templates/run_until_done.sh under mpirun, stopped as a user at a terminal stops it.

A Ctrl-C (SIGINT to the script) makes the solve write its checkpoint and the script exit 75
without starting again; running the script again resumes from the checkpoint and finishes; two
Ctrl-Cs end it at once. Usage: run_until_done_test.py RADIOSITY SOURCE_DIR
"""
import os
import signal
import sys
import time

from template_harness import Checks, Sandbox

radiosity, source = sys.argv[1], sys.argv[2]
script = os.path.join(source, "jobs", "templates", "run_until_done.sh")
checks = Checks()
check = checks.check
box = Sandbox(radiosity)
# Long enough to be stopped in the middle of its form factors on any machine.
job = box.write_job('scene = "builtin:rooms?patches=20000"\noutput = "rooms.h5"\nrays = 4096\n'
                    'estimator = "hemisphere"\n')
checkpoint = box.path("job.checkpoint.h5")
env = {"NP": "2", "CHECKPOINT_EVERY": "0"}

run = box.start(script, [job], env)
check(box.wait_for("form factors:", 120), "the solve started")
time.sleep(1)
run.send_signal(signal.SIGINT)
code = run.wait(timeout=300)
check(code == 75, "one Ctrl-C: exit 75 (was %d)" % code)
check(os.path.exists(checkpoint), "one Ctrl-C: the checkpoint is written")
check(not os.path.exists(box.path("rooms.h5")), "one Ctrl-C: no result yet")
check("restarting" not in box.last_log(), "one Ctrl-C: not started again")

run = box.start(script, [job], env)
code = run.wait(timeout=600)
check(code == 0, "run again: exit 0 (was %d)" % code)
check("restart: " in box.last_log(), "run again: resumed from the checkpoint")
check(os.path.exists(box.path("rooms.h5")), "run again: the result is written")

os.remove(checkpoint)
run = box.start(script, [job], env)
check(box.wait_for("form factors:", 120), "third run started")
run.send_signal(signal.SIGINT)
time.sleep(0.2)
run.send_signal(signal.SIGINT)
code = run.wait(timeout=60)
# (bash ends through SIGINT itself when its INT trap exits, as a shell's Ctrl-C should)
check(code in (130, -signal.SIGINT), "two Ctrl-Cs: ended at once (exit %d)" % code)
check(box.no_rank_left(job), "two Ctrl-Cs: no rank left running")

box.close()
checks.finish()
