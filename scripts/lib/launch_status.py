"""roslaunch with an honest exit status (see scripts/launch): the output passes through
unchanged; a line "process has died [pid N, exit code C, ...]" after "REQUIRED process [...] has
died!" gives the status C."""
import re
import signal
import subprocess
import sys

REQUIRED_DIED = re.compile(r"REQUIRED process \[(?P<node>[^\]]+)\] has died")
PROCESS_DIED = re.compile(r"process has died \[pid \d+, exit code (?P<code>-?\d+)")
FINISHED_CLEANLY = "process has finished cleanly"


def main(arguments):
    # Ctrl-C reaches roslaunch (same process group), which stops its nodes; wait for it.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    process = subprocess.Popen(["roslaunch", *arguments], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, bufsize=1)
    required_failed, status = None, None
    for line in process.stdout:
        sys.stdout.write(line)
        sys.stdout.flush()
        died = REQUIRED_DIED.search(line)
        if died and required_failed is None:
            required_failed = died.group("node")
            continue
        if required_failed is not None and status is None:
            code = PROCESS_DIED.search(line)
            if code:
                status = int(code.group("code"))
            elif FINISHED_CLEANLY in line:
                required_failed, status = None, 0
    launch_status = process.wait()
    if required_failed is not None:
        status = status if status else 1
        if status < 0:
            status = 128 - status  # killed by a signal
        print(f"launch: required node {required_failed} failed with exit status {status}",
              file=sys.stderr)
        return status
    return launch_status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
