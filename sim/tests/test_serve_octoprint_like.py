"""A client that talks to `hotend-sim serve` the way OctoPrint does (its documented protocol):
M110 N0 first, every line numbered and checksummed, one line in flight until its `ok`, M105
polled every 2 s, M115 parsed including `Cap:` lines, `Resend:` honoured, `Error:` watched,
M112 sent at once without waiting for the outstanding `ok`.

usage: test_serve_octoprint_like.py HOTEND_SIM [serve options...]"""
import os
import sys
import threading
import time
from functools import reduce

import serial

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from serve_fixture import Serve, check  # noqa: E402


class OctoLike:
    def __init__(self, device, speed):
        self.port = serial.Serial(device, 115200, timeout=0.05)
        self.speed = speed  # serve's --speed: the host's periods shrink with it
        self.lines, self.sent = [], {}
        self.next_n = 0
        self.ok = threading.Event()
        self.lock = threading.Lock()
        self.resends = []
        self.errors = []
        self.stop = False
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        buf = b""
        while not self.stop:
            try:
                buf += self.port.read(256)
            except serial.SerialException:  # serve ended
                return
            while b"\n" in buf:
                line, buf = buf.split(b"\n", 1)
                self._on_line(line.decode(errors="replace").strip())

    def _on_line(self, line):
        self.lines.append(line)
        if line.startswith("Resend:"):
            self.resends.append(int(line.split(":")[1]))
        elif line.startswith("Error:"):
            self.errors.append(line)
        elif line.startswith("ok"):
            if self.resends:  # resend from the requested line, as OctoPrint does
                n = self.resends.pop()
                self._write(self.sent[n])
                return
            self.ok.set()

    def _write(self, text):
        with self.lock:
            self.port.write((text + "\n").encode())

    def command(self, cmd, timeout=30.0, wait=True):
        n = self.next_n
        body = "N%d %s" % (n, cmd)
        line = "%s*%d" % (body, reduce(lambda a, c: a ^ ord(c), body, 0))
        self.sent[n] = line
        self.next_n = n + 1
        self.ok.clear()
        self._write(line)
        if wait and not self.ok.wait(timeout):
            raise AssertionError("no ok for %s; last lines: %s" % (line, self.lines[-8:]))
        return line

    def reset_line_numbers(self):
        self.next_n = 0
        self.command("M110 N0")  # numbered N0 and checksummed, as OctoPrint sends it
        self.next_n = 1

    def emergency(self):
        self._write("M112")  # unnumbered, immediately, whatever is in flight

    def poll_until(self, done, seconds):
        """M105 every 2 s (host time stretched by --speed) until done() or seconds pass."""
        deadline = time.time() + seconds
        while not done():
            if time.time() > deadline:
                raise AssertionError("timed out; last lines: %s" % self.lines[-8:])
            self.command("M105")
            time.sleep(2.0 / self.speed)


def main():
    sim, serve_args = sys.argv[1], sys.argv[2:]
    speed = float(serve_args[serve_args.index("--speed") + 1]) if "--speed" in serve_args else 1.0
    server = Serve(sim, serve_args)
    print("".join(server.banner), flush=True)
    host = OctoLike(server.device, speed)
    try:
        time.sleep(0.3)
        host.reset_line_numbers()
        check(host.lines and host.lines[-1] == "ok", "M110 N0 acknowledged")
        mark = len(host.lines)
        host.command("M115")
        info = host.lines[mark:]
        caps = dict(l[4:].split(":", 1) for l in info if l.startswith("Cap:"))
        firmware = next(l for l in info if l.startswith("FIRMWARE_NAME:"))
        check(firmware.split()[0] == "FIRMWARE_NAME:hotend-controller", "M115: " + firmware.split()[0])
        check(caps.get("AUTOREPORT_TEMP") == "1" and "EMERGENCY_PARSER" in caps, "M115 capabilities: %s" % caps)

        # A corrupted line: Error + Resend, the host resends the stored line.
        mark = len(host.lines)
        n = host.next_n
        body = "N%d M105" % n
        host.sent[n] = "%s*%d" % (body, reduce(lambda a, c: a ^ ord(c), body, 0))
        host.next_n = n + 1
        host.ok.clear()
        host._write(body + "*0")
        check(host.ok.wait(10), "the corrupted line was resent and acknowledged")
        check(any(l == "Resend: %d" % n for l in host.lines[mark:]), "Resend: %d asked" % n)

        host.command("M104 S150")
        temps = []

        def hot():
            reps = [l for l in host.lines if l.startswith("ok T:")]
            if reps:
                temps.append(float(reps[-1].split("T:")[1].split()[0]))
            return temps and temps[-1] >= 148.0

        host.poll_until(hot, 60)
        check(len(temps) >= 3, "M105 polled every 2 s while heating: %s" % temps[-5:])

        mark = len(host.lines)
        host.command("M109 S160", wait=False)  # in flight: its ok comes only when hot
        time.sleep(0.5)
        host.emergency()
        deadline = time.time() + 10
        while not any(l.startswith("Error:") and "M112" in l for l in host.lines[mark:]) and time.time() < deadline:
            time.sleep(0.05)
        check(any(l.startswith("Error:") and "M112" in l for l in host.lines[mark:]),
              "M112 sent during M109's wait stopped it: %s" % [l for l in host.lines[mark:] if l.startswith("Error")])
        time.sleep(0.3)
        host.ok.clear()
        host._write("M105")
        host.ok.wait(5)
        last = [l for l in host.lines if "T:" in l][-1]
        check("/0.00" in last and "@:0" in last, "heater off after M112: " + last)
    finally:
        host.stop = True
        code, report = server.stop()
        print(report)
    check(code == 0, "serve exited 0 after SIGINT")


if __name__ == "__main__":
    main()
