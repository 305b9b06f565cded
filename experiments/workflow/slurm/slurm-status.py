#!/usr/bin/python3
"""Snakemake cluster-status for Slurm: prints running, success or failed for a job id, asking
scontrol (jobs Slurm still holds) and then sacct (accounting, for jobs already purged)."""
import subprocess
import sys

FAILED = {"FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY", "PREEMPTED", "BOOT_FAIL", "DEADLINE"}


def state_of(job_id):
    r = subprocess.run(["scontrol", "show", "job", job_id], capture_output=True, text=True)
    if r.returncode == 0:
        for word in r.stdout.split():
            if word.startswith("JobState="):
                return word.split("=", 1)[1]
    r = subprocess.run(["sacct", "-j", job_id, "--format=State", "--noheader", "--parsable2", "-X"],
                       capture_output=True, text=True)
    if r.returncode == 0 and r.stdout.strip():
        return r.stdout.split()[0].split()[0]
    return "UNKNOWN"


def main():
    state = state_of(sys.argv[1])
    if state == "COMPLETED":
        print("success")
    elif state.split(" ")[0] in FAILED or state.startswith("CANCELLED"):
        print("failed")
    else:
        print("running")


if __name__ == "__main__":
    main()
