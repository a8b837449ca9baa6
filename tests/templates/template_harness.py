"""What the batch-template tests share: checks that report and count, and a sandbox folder with
stand-ins for the scheduler's commands (sbatch/scontrol/squeue, qsub/qstat), which record what
would have been submitted, and for mpirun (the real one with two ranks, outside any scheduler).
"""
import os
import stat
import subprocess
import sys
import tempfile
import time


class Checks:
    def __init__(self):
        self.failures = []
        self.count = 0

    def check(self, condition, what):
        self.count += 1
        print(("ok: " if condition else "FAIL: ") + what, flush=True)
        if not condition:
            self.failures.append(what)

    def finish(self):
        print("%d passed, %d failed" % (self.count - len(self.failures), len(self.failures)))
        sys.exit(1 if self.failures else 0)


# The stand-ins. Each scheduler command appends its arguments to FOLDER/submitted.txt and prints
# what the test put in FAKE_* variables; mpirun is the real one (on two ranks unless -n), with the
# scheduler's variables removed (Open MPI would otherwise look for a SLURM or PBS allocation).
STAND_INS = {
    "scontrol": 'echo "scontrol $*" >> "$SANDBOX/submitted.txt"\n',
    "sbatch": 'echo "sbatch $*" >> "$SANDBOX/submitted.txt"\n',
    "qsub": 'echo "qsub $*" >> "$SANDBOX/submitted.txt"\necho 78.pbs\n',
    "squeue": 'echo "${FAKE_TIME_LEFT:-UNLIMITED}"\n',
    "qstat": '[[ -n ${FAKE_WALLTIME:-} ]] && echo "    Resource_List.walltime = $FAKE_WALLTIME"\n'
             'echo "    job_state = R"\n',
    "mpirun": 'for v in $(compgen -e | grep -E "^(SLURM|PBS)_"); do unset "$v"; done\n'
              '[[ $1 == -n ]] || set -- -n 2 "$@"\n'
              'exec "$REAL_MPIRUN" "$@"\n',
}


class Sandbox:
    """A temporary folder with bin/ (the stand-ins) first on PATH."""

    def __init__(self, radiosity):
        self.radiosity = radiosity
        self.holder = tempfile.TemporaryDirectory()
        self.folder = self.holder.name
        self.bin = os.path.join(self.folder, "bin")
        os.mkdir(self.bin)
        real_mpirun = subprocess.run(["bash", "-c", "command -v mpirun"], capture_output=True,
                                     text=True).stdout.strip()
        for name, body in STAND_INS.items():
            self.write_script(name, body)
        self.base_env = dict(os.environ, SANDBOX=self.folder, REAL_MPIRUN=real_mpirun,
                             PATH=self.bin + os.pathsep + os.environ["PATH"],
                             RADIOSITY=radiosity, OMPI_ALLOW_RUN_AS_ROOT="1",
                             OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                             OMPI_MCA_rmaps_base_oversubscribe="1")
        self.log_path = os.path.join(self.folder, "log.txt")

    def write_script(self, name, body):
        path = os.path.join(self.bin, name)
        with open(path, "w") as f:
            f.write("#!/usr/bin/env bash\n" + body)
        os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
        return path

    def path(self, name):
        return os.path.join(self.folder, name)

    def write_job(self, text, name="job.toml"):
        with open(self.path(name), "w") as f:
            f.write(text)
        return self.path(name)

    def start(self, script, arguments=(), env=None, new_session=False):
        """The template as the scheduler starts it, its output appended to log.txt."""
        log = open(self.log_path, "a")
        log.write("\n=== %s %s %s\n" % (os.path.basename(script), " ".join(arguments), env or ""))
        log.flush()
        return subprocess.Popen(["bash", script, *arguments], cwd=self.folder,
                                env=dict(self.base_env, **(env or {})), stdout=log,
                                stderr=subprocess.STDOUT, start_new_session=new_session)

    def log(self):
        with open(self.log_path) as f:
            return f.read()

    def last_log(self):
        """The output of the last template started."""
        return self.log().rsplit("\n=== ", 1)[-1]

    def submitted(self):
        if not os.path.exists(self.path("submitted.txt")):
            return []
        with open(self.path("submitted.txt")) as f:
            return f.read().splitlines()

    def wait_for(self, text, seconds):
        """Until the last template's output holds `text`."""
        end = time.time() + seconds
        while time.time() < end:
            if text in self.last_log():
                return True
            time.sleep(0.1)
        return False

    def no_rank_left(self, job):
        time.sleep(2)
        left = subprocess.run(["pgrep", "-f", "solve --config " + job], capture_output=True,
                              text=True)
        return left.stdout.strip() == ""

    def close(self):
        self.holder.cleanup()


def interrupt_group(process, signal_number):
    """A signal to the process group the template leads, as PBS signals the job's session."""
    os.killpg(process.pid, signal_number)
