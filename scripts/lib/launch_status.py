"""roslaunch with an honest exit status (see scripts/launch).

Before anything starts, an argument NAME:=VALUE that the launch file does not declare is
refused (roslaunch itself ignores it without a word), naming the closest declared one.
roslaunch's output passes through, but for its red "REQUIRED process [...] has died! process has
finished cleanly" banner when the required node ended with status 0: a finished run, which ends
with our own line instead. A real failure keeps the banner, and the status C of its line
"process has died [pid N, exit code C, ...]" is ours. SIGINT, SIGTERM or SIGHUP stop roslaunch
and its nodes, remove the staging folders (".NAME.partial-PID") that the stopped run left under
the folders its arguments name, and exit 128 + the signal's number."""
import difflib
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree

from granular_tools.output import process_running

REQUIRED_DIED = re.compile(r"REQUIRED process \[(?P<node>[^\]]+)\] has died")
PROCESS_DIED = re.compile(r"process has died \[pid \d+, exit code (?P<code>-?\d+)")
FINISHED_CLEANLY = "process has finished cleanly"
BANNER_END = "=" * 80
STAGING = re.compile(r"^\..+\.partial-(?P<pid>\d{1,9})(\.\w+)?$")
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
STAGING_DEPTH = 3  # folders below a named folder searched for staging (OUT/models/.pictures...)
RED, PLAIN = "\033[31m", "\033[0m"


class BadArgument(Exception):
    pass


def launch_files(arguments):
    """The launch files roslaunch would run for `arguments` (roslaunch's own resolution); none
    when it cannot tell, so that roslaunch reports what is wrong."""
    try:
        import roslaunch
        from roslaunch import rlutil
        # roslaunch's own options first (--screen, -p PORT, ...), as roslaunch parses them.
        _, positional = roslaunch._get_optparse().parse_args(list(arguments))
        return [path for path in rlutil.resolve_launch_arguments(positional)
                if os.path.isfile(path)]
    except Exception:  # noqa: BLE001 - roslaunch names the problem itself
        return []


def declared_arguments(launch_file):
    """The names of the <arg>s `launch_file` declares (those inside an <include> pass values
    to the included file and are not its own)."""
    names = set()
    for element in ElementTree.parse(launch_file).getroot().iter():
        if element.tag != "include":
            names.update(child.get("name") for child in element if child.tag == "arg")
    return names


def check_arguments(arguments):
    """BadArgument naming the first NAME:=VALUE that no launch file of `arguments` declares."""
    files = launch_files(arguments)
    if not files:
        return
    try:
        declared = set().union(*(declared_arguments(path) for path in files))
    except ElementTree.ParseError:
        return  # roslaunch says where the file is broken
    for argument in arguments:
        name = argument.split(":=", 1)[0]
        if ":=" not in argument or name.startswith("_") or name in declared:
            continue
        close = difflib.get_close_matches(name, sorted(declared), n=1)
        hint = f"did you mean {close[0]}:=? " if close else ""
        names = ", ".join(os.path.basename(path) for path in files)
        raise BadArgument(f"{names} takes no argument '{name}' ({hint}its arguments: "
                          f"{', '.join(sorted(declared)) or 'none'})")


def named_folders(arguments):
    """Where a run's staging is built, as {folder: how many levels below it to search}: each
    folder an argument's value names (OUT, searched STAGING_DEPTH deep) and the folder holding
    each named path (only its own entries: OUT's staging is OUT's sibling)."""
    folders = {}
    for argument in arguments:
        value = argument.split(":=", 1)[1] if ":=" in argument else ""
        if not value:
            continue
        path = os.path.abspath(value)
        folders.setdefault(os.path.dirname(path), 0)
        if os.path.isdir(path):
            folders[path] = STAGING_DEPTH
    return folders


def remove_staging(arguments, since):
    """Remove the staging folders and files that a process of this run, now dead, left under
    the folders its arguments name (made since `since`, by a process no longer alive)."""
    removed = []
    for root, depth in named_folders(arguments).items():
        base_depth = root.rstrip(os.sep).count(os.sep)
        for folder, subfolders, files in os.walk(root):
            names = subfolders + files
            if folder.rstrip(os.sep).count(os.sep) - base_depth >= depth:
                subfolders[:] = []  # its own entries only
            for name in names:
                match = STAGING.match(name)
                path = os.path.join(folder, name)
                if not match or process_running(int(match.group("pid"))):
                    continue
                try:
                    if os.lstat(path).st_mtime < since:
                        continue
                    if os.path.isdir(path) and not os.path.islink(path):
                        shutil.rmtree(path)
                    else:
                        os.remove(path)
                except OSError:
                    continue  # gone meanwhile, or not ours to remove: the next run clears it
                if name in subfolders:
                    subfolders.remove(name)
                removed.append(path)
    return removed


def relay(process):
    """Pass roslaunch's output on, but for the banner of a required node that finished with
    status 0; (the required node that died, its exit status) or (None, None)."""
    required, status, banner, hiding = None, None, [], False
    for line in process.stdout:
        if hiding:
            hiding = BANNER_END not in line  # the banner's last line
            continue
        died = REQUIRED_DIED.search(line)
        if died and required is None:
            required, banner = died.group("node"), [line]
            continue
        if banner:
            banner.append(line)
            code = PROCESS_DIED.search(line)
            if code or "has died" in line:
                status = int(code.group("code")) if code else 1
                sys.stdout.writelines(banner)  # a failure: roslaunch's red banner stays
                banner = []
            elif FINISHED_CLEANLY in line:
                status, banner, hiding = 0, [], True
            sys.stdout.flush()
            continue
        sys.stdout.write(line)
        sys.stdout.flush()
    sys.stdout.writelines(banner)  # one whose status never came
    return required, status


def main(arguments):
    try:
        check_arguments(arguments)
    except BadArgument as error:
        print(f"launch: {error}", file=sys.stderr)
        return 2
    started = time.time()
    stopped, launched = [], []

    def stop(signum, _frame):
        # roslaunch runs in its own process group, so that a Ctrl-C reaches it once, from
        # here; it stops its nodes (SIGINT, then SIGTERM) before it exits.
        if not stopped:
            stopped.append(signum)
            for process in launched:
                process.send_signal(signal.SIGINT)

    for signum in STOP_SIGNALS:
        signal.signal(signum, stop)
    process = subprocess.Popen(["roslaunch", *arguments], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, bufsize=1,
                               errors="replace", process_group=0)
    launched.append(process)
    if stopped:
        process.send_signal(signal.SIGINT)
    required, status = relay(process)
    launch_status = process.wait()
    if required is not None:
        required = re.sub(r"-\d+$", "", required)  # roslaunch's process name: the node's, numbered
    if stopped:
        removed = remove_staging(arguments, started)
        tail = f"; removed the partial output {', '.join(removed)}" if removed else ""
        print(f"launch: interrupted by {signal.Signals(stopped[0]).name}; roslaunch and its "
              f"nodes stopped{tail}", file=sys.stderr)
        return 128 + stopped[0]
    if required is not None and status != 0:
        status = status if status else 1
        if status < 0:
            status = 128 - status  # killed by a signal
        red, plain = (RED, PLAIN) if sys.stderr.isatty() else ("", "")
        print(f"{red}launch: required node {required} failed with exit status {status}{plain}",
              file=sys.stderr)
        return status
    if required is not None:
        print(f"launch: done ({required} finished with exit status 0)", file=sys.stderr)
    return launch_status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
