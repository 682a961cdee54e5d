"""printrun's printcore (the library behind Pronterface and pronsole) on `hotend-sim serve`.

usage: test_serve_printcore.py HOTEND_SIM PRINTCORE_SITE_DIR [serve options...]
Checks the first `ok`, M105's format (printrun's own parser), M104/M109 with the wait lines,
checksummed lines with a forced resend, M303 ... U1 output, and M112."""
import os
import sys
import threading
import time

sys.path.insert(0, sys.argv[2])
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from printrun.printcore import printcore  # noqa: E402
from printrun import gcoder  # noqa: E402
from printrun.utils import parse_temperature_report  # noqa: E402
from serve_fixture import Serve, check  # noqa: E402


class Lines:
    """Every line printcore receives, with a wait-for helper."""

    def __init__(self):
        self.lines = []
        self.cond = threading.Condition()

    def add(self, line):
        with self.cond:
            self.lines.append(line.rstrip())
            self.cond.notify_all()

    def wait_for(self, predicate, timeout, start=0):
        deadline = time.time() + timeout
        with self.cond:
            while True:
                for i in range(start, len(self.lines)):
                    if predicate(self.lines[i]):
                        return i
                left = deadline - time.time()
                if left <= 0:
                    raise AssertionError("timed out; last lines:\n" + "\n".join(self.lines[-15:]))
                self.cond.wait(left)


def main():
    sim, site, serve_args = sys.argv[1], sys.argv[2], sys.argv[3:]
    server = Serve(sim, serve_args)
    print("".join(server.banner), flush=True)
    got = Lines()
    p = printcore()
    p.recvcb = got.add
    sent = []
    p.sendcb = lambda command, gline: sent.append(command)
    p.connect(server.device, 115200)
    try:
        deadline = time.time() + 20
        while not p.online and time.time() < deadline:
            time.sleep(0.05)
        check(p.online, "printcore online: the first `ok` (or `start`) answered its M105")

        mark = len(got.lines)
        p.send_now("M105")
        i = got.wait_for(lambda l: l.startswith("ok T:"), 10, mark)
        report = parse_temperature_report(got.lines[i])
        check("T" in report and float(report["T"][0]) > 15 and report["T"][1] != "",
              "M105: `%s` parsed by printrun as %s" % (got.lines[i], report))

        mark = len(got.lines)
        p.send_now("M104 S120")
        got.wait_for(lambda l: l == "ok", 10, mark)
        p.send_now("M109 S120")
        j = got.wait_for(lambda l: l == "ok", 120, mark + 1)
        waits = [l for l in got.lines[mark:j] if l.startswith(" T:") or l.startswith("T:")]
        check(len(waits) >= 3, "M109 S120: %d wait-and-report lines before its ok (last: %s)"
              % (len(waits), waits[-1] if waits else "-"))
        final = parse_temperature_report(waits[-1])
        check(abs(float(final["T"][0]) - 120) <= 1.5, "M109 returned at %s °C" % final["T"][0])

        # A checksummed "print": the third line leaves with a wrong checksum once (a line
        # corrupted on the wire); the firmware asks for it again and printcore resends it.
        real_write = p.printer.write
        corrupted = []

        def corrupting_write(data):
            text = data.decode()
            if text.startswith("N2 ") and not corrupted:
                corrupted.append(text.strip())
                data = (text[:text.index("*") + 1] + "0\n").encode()
            return real_write(data)

        p.printer.write = corrupting_write
        mark = len(got.lines)
        p.startprint(gcoder.LightGCode(["M105", "M106 S128", "M104 S120", "M107", "M105"]))
        deadline = time.time() + 30
        while (p.printing or not corrupted) and time.time() < deadline:
            time.sleep(0.05)
        p.printer.write = real_write
        check(not p.printing, "the checksummed lines were all sent")
        check(any(l.startswith("Resend: 2") for l in got.lines[mark:]),
              "the corrupted `%s` was answered by `Resend: 2`" % corrupted[0])
        check(sent.count(corrupted[0]) == 2 and any(s.startswith("N4 ") for s in sent),
              "printcore resent N2 and went on: " + ", ".join(s for s in sent if s.startswith("N")))
        check(not any(l.startswith("Error:") and "checksum" not in l for l in got.lines[mark:]),
              "no Error: other than the checksum one")

        mark = len(got.lines)
        p.send_now("M303 E0 S150 C3 U1")
        k = got.wait_for(lambda l: l.startswith("echo:Autotune applied") or "Autotune failed" in l, 150, mark)
        tune = got.lines[mark:k + 1]
        print("\n".join("  < " + l for l in tune), flush=True)
        check(any(l.startswith("PID Autotune finished!") for l in tune), "M303 finished")
        check(sum(l.startswith(" bias:") for l in tune) >= 3, "M303 printed its relay cycles")
        check(any("Kp:" in l or "M301" in l for l in tune), "M303 printed the PID it designed")
        check(tune[-1].startswith("echo:Autotune applied"), "U1 applied: " + tune[-1])

        mark = len(got.lines)
        p.send_now("M104 S150")
        got.wait_for(lambda l: l == "ok", 10, mark)
        p.send_now("M112")
        e = got.wait_for(lambda l: l.startswith("Error:"), 10, mark)
        check("M112" in got.lines[e] or "top" in got.lines[e], "M112 answered: " + got.lines[e])
        mark = len(got.lines)
        time.sleep(0.5)
        p.send_now("M105")
        r = got.wait_for(lambda l: "T:" in l, 10, mark)
        check("@:0" in got.lines[r] and "/0.00" in got.lines[r], "after M112 the heater is off: " + got.lines[r])
    finally:
        p.disconnect()
        code, report = server.stop()
        print(report)
    check(code == 0, "serve exited 0 after SIGINT")
    check("session" in report and "T: reports" in report, "serve printed the session's report")


if __name__ == "__main__":
    main()
