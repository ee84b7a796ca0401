#!/usr/bin/env python3
"""Fails when ctest reported a test as skipped, disabled or not run that tests/skip_allowlist.txt
does not allow (issue 28: a test can pass without testing when its set-up fails and gtest reports
it as skipped).

    python3 scripts/check_skips.py build/ctest_junit.xml tests/skip_allowlist.txt

Reads the JUnit file ctest writes with --output-junit; prints every skip with its reason (allowed
or not) and exits 1 when any is not allowed, or when the file holds no test at all.
"""
import re
import sys
import xml.etree.ElementTree as ET


def allow_list(path):
    rules = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            pattern, _, reason = line.partition("|")
            if not reason.strip():
                sys.exit(f"{path}:{number}: expected REGEX | REASON")
            rules.append((re.compile(pattern.strip()), reason.strip()))
    return rules


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: check_skips.py CTEST_JUNIT.xml ALLOWLIST.txt")
    junit, allowed = sys.argv[1], allow_list(sys.argv[2])
    cases = ET.parse(junit).getroot().iter("testcase")
    total, bad = 0, []
    for case in cases:
        total += 1
        name = case.get("name", "")
        status = (case.get("status") or "").lower()
        skipped = case.find("skipped")
        if skipped is None and status not in ("notrun", "disabled", "skipped"):
            continue
        why = (skipped.get("message") if skipped is not None else "") or status
        rule = next((r for r in allowed if r[0].fullmatch(name)), None)
        if rule:
            print(f"check_skips: allowed skip: {name} ({rule[1]})")
        else:
            bad.append(f"{name}: {why}")
    if total == 0:
        sys.exit(f"check_skips: {junit} holds no test")
    for b in bad:
        print(f"check_skips: SKIPPED TEST NOT ON THE ALLOW-LIST: {b}", file=sys.stderr)
    if bad:
        print("check_skips: a skipped test did not test anything; fix its set-up or add it to tests/skip_allowlist.txt "
              "with the reason", file=sys.stderr)
        return 1
    print(f"check_skips: {total} tests, no unexpected skip")
    return 0


if __name__ == "__main__":
    sys.exit(main())
