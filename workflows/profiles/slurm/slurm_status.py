#!/usr/bin/python3
"""Snakemake --cluster-status for SLURM: print running, success or failed for a job id.

Uses `scontrol show job` (it needs no accounting database, unlike sacct); a job that
scontrol no longer knows has left the controller's memory (MinJobAge, 300 s by default)
after finishing: Snakemake checks its outputs then, so 'success' is the safe answer only
when the job was seen to complete; otherwise we fall back to sacct when it exists.
"""
import subprocess
import sys

RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED", "RESIZING",
           "STAGE_OUT", "SIGNALING"}
SUCCESS = {"COMPLETED"}


def state_from_scontrol(job: str) -> str | None:
    p = subprocess.run(["scontrol", "show", "job", "-o", job], capture_output=True, text=True)
    if p.returncode != 0:
        return None
    for field in p.stdout.split():
        if field.startswith("JobState="):
            return field.split("=", 1)[1]
    return None


def state_from_sacct(job: str) -> str | None:
    try:
        p = subprocess.run(["sacct", "-n", "-X", "-P", "-o", "State", "-j", job],
                           capture_output=True, text=True)
    except FileNotFoundError:
        return None
    words = p.stdout.split()
    return words[0] if p.returncode == 0 and words else None


def main() -> int:
    job = sys.argv[1]
    state = state_from_scontrol(job) or state_from_sacct(job)
    if state is None:
        # Neither knows the job: it finished long enough ago to be purged. Snakemake then
        # verifies the declared outputs itself, so a job that failed is still caught.
        print("success")
    elif state in RUNNING:
        print("running")
    elif state in SUCCESS:
        print("success")
    else:  # FAILED, TIMEOUT, CANCELLED, NODE_FAIL, OUT_OF_MEMORY, PREEMPTED, BOOT_FAIL, DEADLINE
        print("failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
