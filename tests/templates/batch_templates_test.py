"""jobs/templates/slurm.sbatch and pbs.sh under mpirun, as far as can be done without a
scheduler: stand-ins for squeue/scontrol and qstat/qsub record what would be submitted
(template_harness.py). For each template: a chunk stopped by --stop-after from the time left,
the requeued (resubmitted) chunk resuming to the end, the scheduler's signal path, the requeue
cap and the no-progress stop, and every documented setting reaching the next chunk. Usage: batch_templates_test.py RADIOSITY SOURCE_DIR
"""
import os
import signal
import sys

from template_harness import Checks, Sandbox, interrupt_group

radiosity, source = sys.argv[1], sys.argv[2]
slurm = os.path.join(source, "jobs", "templates", "slurm.sbatch")
pbs = os.path.join(source, "jobs", "templates", "pbs.sh")
checks = Checks()
check = checks.check
# A few seconds on two ranks: long enough for a stop in the middle of the form factors.
JOB = ('scene = "builtin:rooms?patches=20000"\noutput = "rooms.h5"\nrays = 2048\n'
       'estimator = "hemisphere"\nquiet = false\n')
# A stand-in solver for the cap and the no-progress stop: every "solve" stops with 75 and, unless
# FAKE_NO_PROGRESS is set, adds a line to what `info` shows of the checkpoint.
FAKE_RADIOSITY = ('case $1 in\n'
                  '  info) cat "$SANDBOX/progress" 2>/dev/null ;;\n'
                  '  solve) [[ -n ${FAKE_NO_PROGRESS:-} ]] || echo step >> "$SANDBOX/progress"\n'
                  '         exit 75 ;;\n'
                  'esac\n')


def stop_and_resume(template, name, env, resumed_env, stop_env):
    """Chunk 1 stops on its own clock (--stop-after) and submits its successor; chunk 2, as the
    scheduler starts it, resumes from the checkpoint and writes the result."""
    box = Sandbox(radiosity)
    job = box.write_job(JOB)
    run = box.start(template, *env(box, job, stop_env))
    code = run.wait(timeout=300)
    check(code == 75, "%s: stopped before the time limit, exit 75 (was %d)" % (name, code))
    check("stopped by --stop-after 2 s" in box.last_log(),
          "%s: by --stop-after, from the time the scheduler says is left" % name)
    check(os.path.exists(box.path("job.checkpoint.h5")), "%s: the checkpoint is written" % name)
    check(not os.path.exists(box.path("rooms.h5")), "%s: no result yet" % name)
    first = box.submitted()
    run = box.start(template, *env(box, job, resumed_env))
    code = run.wait(timeout=600)
    check(code == 0, "%s: the next chunk finishes, exit 0 (was %d)" % (name, code))
    check("restart: " in box.last_log(), "%s: the next chunk resumed from the checkpoint" % name)
    check(os.path.exists(box.path("rooms.h5")), "%s: the result is written" % name)
    check(box.submitted() == first, "%s: nothing submitted after the last chunk" % name)
    box.close()
    return first


def settings_survive(template, name, env, first_env, successor_env, count_variable, cap_word):
    """Every documented setting reaches the chunk after the first as the scheduler would start
    it: `successor_env(first_env, submitted)` is that chunk's environment (SLURM: the job's own,
    kept by the requeue; PBS: only what the successor's `qsub -v` names). With MARGIN 1 it
    stops on its clock again, from its CHECKPOINT, run by its RADIOSITY, and at MAX_* 1 it
    submits nothing more."""
    box = Sandbox(radiosity)
    job = box.write_job(JOB)
    wrapper = box.write_script("my_radiosity",
                               'echo "$*" >> "$SANDBOX/wrapper.txt"\nexec %s "$@"\n' % radiosity)
    settings = {"MARGIN": "1", count_variable: "1", "CHECKPOINT": box.path("mine.ckpt.h5"),
                "RADIOSITY": wrapper}
    arguments, environment = env(box, job, dict(first_env, **settings))
    code = box.start(template, arguments, environment).wait(timeout=300)
    check(code == 75 and len(box.submitted()) == 1, "%s settings: the first chunk stops and "
          "submits its successor (exit %d, %s)" % (name, code, box.submitted()))
    arguments, environment = successor_env(box, job, environment, box.submitted()[0])
    code = box.start(template, arguments, environment).wait(timeout=300)
    log = box.last_log()
    check(code == 75 and "stopped by --stop-after 2 s" in log,
          "%s settings: MARGIN reaches the next chunk (exit %d)" % (name, code))
    check("restart: " in log and box.path("mine.ckpt.h5") in log,
          "%s settings: CHECKPOINT reaches the next chunk" % name)
    with open(box.path("wrapper.txt")) as f:  # (a line per rank)
        solves = [line for line in f if line.startswith("solve ")]
    check(any("--restart" in line for line in solves) and
          any("--restart" not in line for line in solves),
          "%s settings: RADIOSITY runs both chunks" % name)
    check(len(box.submitted()) == 1 and cap_word in log,
          "%s settings: %s reaches the next chunk: at the cap, nothing more" % (name, cap_word))
    box.close()


def slurm_requeued_env(box, job, environment, submitted):
    """`scontrol requeue` starts the job again with the environment it was submitted with."""
    return [job], dict(environment, SLURM_RESTART_COUNT="1")


def pbs_successor_env(box, job, environment, submitted):
    """`qsub -v A=1,B=2 script` gives the job those variables and none of the submitter's."""
    named = dict(item.split("=", 1) for item in submitted.split(" -v ")[1].split(" ")[0].split(","))
    stand_ins = {key: value for key, value in environment.items() if key.startswith("FAKE_")}
    return [], dict(PBS_JOBID="78.pbs", PBS_O_WORKDIR=box.folder, **stand_ins, **named)


def signalled(template, name, env, send):
    """The scheduler's signal before the limit: the checkpoint, exit 75 and a successor."""
    box = Sandbox(radiosity)
    job = box.write_job(JOB)
    arguments, environment = env(box, job, {})
    run = box.start(template, arguments, environment, new_session=True)
    check(box.wait_for("form factors:", 120), "%s: the solve started" % name)
    send(run)
    code = run.wait(timeout=300)
    log = box.last_log()
    check(code == 75, "%s: exit 75 (was %d)" % (name, code))
    check("stopped by SIGUSR1" in log, "%s: the ranks were asked with SIGUSR1" % name)
    check(os.path.exists(box.path("job.checkpoint.h5")), "%s: the checkpoint is written" % name)
    check(box.no_rank_left(job), "%s: no rank left running" % name)
    submitted = box.submitted()
    box.close()
    return submitted


def capped(template, name, env, count_variable, cap):
    """A chunk that stops without progress, or at the cap, submits nothing."""
    box = Sandbox(radiosity)
    job = box.write_job(JOB)
    fake = box.write_script("fake_radiosity", FAKE_RADIOSITY)
    for extra, wanted, what in [
        ({count_variable: "3"}, 1, "a chunk that made progress is followed by another"),
        ({count_variable: str(cap)}, 0, "at the cap (%s=%d) nothing more" % (count_variable, cap)),
        ({count_variable: "3", "FAKE_NO_PROGRESS": "1"}, 0, "a chunk without progress stops it"),
    ]:
        before = len(box.submitted())
        arguments, environment = env(box, job, dict(extra, RADIOSITY=fake))
        code = box.start(template, arguments, environment).wait(timeout=120)
        check(code == 75 and len(box.submitted()) - before == wanted, "%s: %s" % (name, what))
    check("without progress" in box.last_log(), "%s: says it stopped without progress" % name)
    box.close()


def slurm_env(box, job, extra):
    return [job], dict(SLURM_JOB_ID="1234", SLURM_SUBMIT_DIR=box.folder, **extra)


def pbs_env(box, job, extra):
    return [], dict(PBS_JOBID="77.pbs", PBS_O_WORKDIR=box.folder, JOB=job, **extra)


# SLURM: the time left comes from squeue (%L), the successor is `scontrol requeue`.
submitted = stop_and_resume(slurm, "slurm", slurm_env,
                            resumed_env={"SLURM_RESTART_COUNT": "1"},
                            stop_env={"FAKE_TIME_LEFT": "0:03", "MARGIN": "1"})
check(submitted == ["scontrol requeue 1234"], "slurm: requeued itself (%s)" % submitted)
# SLURM's --signal=B:USR1 signals the batch shell only.
submitted = signalled(slurm, "slurm signal", slurm_env, lambda run: run.send_signal(signal.SIGUSR1))
check(submitted == ["scontrol requeue 1234"], "slurm signal: requeued itself (%s)" % submitted)
capped(slurm, "slurm", slurm_env, "SLURM_RESTART_COUNT", 20)
settings_survive(slurm, "slurm", slurm_env, {"FAKE_TIME_LEFT": "0:03"}, slurm_requeued_env,
                 "MAX_REQUEUES", "MAX_REQUEUES")

# PBS: the walltime comes from qstat, the successor is a qsub depending on this job.
submitted = stop_and_resume(pbs, "pbs", pbs_env, resumed_env={"RESUBMITS": "1"},
                            stop_env={"FAKE_WALLTIME": "00:00:03", "MARGIN": "1",
                                      "MAX_RESUBMITS": "7"})
check(len(submitted) == 1 and submitted[0].startswith("qsub -W depend=afterany:77.pbs -v JOB=")
      and "RESUBMITS=1" in submitted[0] and submitted[0].endswith(pbs),
      "pbs: submitted its successor after this job (%s)" % submitted)
# qsub -v passes only the variables it names: every documented setting must be among them.
check(len(submitted) == 1 and all(setting in submitted[0] for setting in
                                  ["MARGIN=1,", "MAX_RESUBMITS=7", "CHECKPOINT=", "RADIOSITY="]),
      "pbs: the successor keeps MARGIN, MAX_RESUBMITS, CHECKPOINT and RADIOSITY (%s)" % submitted)
# PBS signals every process of the job's session with SIGTERM; mpirun, in a session of its own,
# is asked with SIGUSR1 instead.
submitted = signalled(pbs, "pbs signal", pbs_env,
                      lambda run: interrupt_group(run, signal.SIGTERM))
check(len(submitted) == 1 and "depend=afterany:77.pbs" in submitted[0],
      "pbs signal: submitted its successor (%s)" % submitted)
capped(pbs, "pbs", pbs_env, "RESUBMITS", 20)
settings_survive(pbs, "pbs", pbs_env, {"FAKE_WALLTIME": "00:00:03"}, pbs_successor_env,
                 "MAX_RESUBMITS", "MAX_RESUBMITS")

checks.finish()
