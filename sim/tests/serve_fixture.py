"""Starts `hotend-sim serve` for a host test and stops it with SIGINT, returning its report.

Used by the printcore and OctoPrint-like tests (sim/CMakeLists.txt registers them)."""
import re
import signal
import subprocess
import time


class Serve:
    def __init__(self, sim, args):
        self.proc = subprocess.Popen([sim, "serve", *args], stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True)
        self.banner = []
        self.device = None
        deadline = time.time() + 20
        while self.device is None:
            line = self.proc.stdout.readline()
            if not line or time.time() > deadline:
                raise RuntimeError("serve did not print its device:\n" + "".join(self.banner))
            self.banner.append(line)
            m = re.match(r"serial port\s+(\S+)", line)
            if m:
                self.device = m.group(1)
        # the rest of the banner up to the Ctrl-C hint
        while not self.banner[-1].startswith("Ctrl-C"):
            self.banner.append(self.proc.stdout.readline())

    def stop(self):
        """SIGINT, as Ctrl-C: returns (exit code, the session's report)."""
        self.proc.send_signal(signal.SIGINT)
        out, _ = self.proc.communicate(timeout=30)
        return self.proc.returncode, out


def check(condition, what):
    if not condition:
        raise AssertionError(what)
    print("PASS", what, flush=True)
