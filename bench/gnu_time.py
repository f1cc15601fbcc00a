"""What /usr/bin/time -v wrote: wall seconds, CPU seconds (user + system), peak MB."""
import re


def time_of(path):
    t = open(path).read()

    def field(label):
        m = re.search(re.escape(label) + r":\s*(\S+)", t)
        return m.group(1) if m else "0"

    wall = field("Elapsed (wall clock) time (h:mm:ss or m:ss)")
    seconds = sum(float(p) * 60 ** i for i, p in enumerate(reversed(wall.split(":"))))
    cpu = float(field("User time (seconds)")) + float(field("System time (seconds)"))
    return seconds, cpu, float(field("Maximum resident set size (kbytes)")) / 1024
