"""Stopping a child process, one way for the tests, the tools and the benchmarks."""

import os
import signal
import subprocess


def stop(process, sig=signal.SIGTERM, timeout=10.0, group=False):
    """Ends `process` (a subprocess.Popen) and reaps it: `sig` first, then SIGKILL when it has
    not ended `timeout` seconds later. With `group` both go to its process group (a process
    started with start_new_session=True: its own children get them too). A process that has
    ended already is only reaped. Returns True when it ended without the SIGKILL."""
    if process.poll() is not None:
        return True

    def send(number):
        try:
            if group:
                os.killpg(process.pid, number)
            else:
                process.send_signal(number)
        except ProcessLookupError:  # ended in the meantime: the wait below reaps it
            pass

    send(sig)
    try:
        process.wait(timeout=timeout)
        return True
    except subprocess.TimeoutExpired:
        send(signal.SIGKILL)
        process.wait()
        return False
