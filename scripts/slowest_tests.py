#!/usr/bin/env python3
"""Prints the N slowest tests of a ctest JUnit file (ctest --output-junit FILE).

usage: scripts/slowest_tests.py JUNIT_XML [N]   (N: 15 by default)
"""
import sys
import xml.etree.ElementTree as ET


def main(argv: list[str]) -> int:
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    try:
        count = int(argv[2]) if len(argv) > 2 else 15
        root = ET.parse(argv[1]).getroot()
    except (OSError, ET.ParseError, ValueError) as e:
        print(f"slowest_tests.py: {e}", file=sys.stderr)
        return 2
    times = [(float(case.get("time", "0")), case.get("name", "?")) for case in root.iter("testcase")]
    times.sort(reverse=True)
    total = sum(t for t, _ in times)
    print(f"slowest tests ({len(times)} tests, {total:.0f} s of test time in all):")
    for t, name in times[:count]:
        print(f"  {t:7.1f} s  {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
