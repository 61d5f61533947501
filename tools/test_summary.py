#!/usr/bin/env python3
"""Prints 'N passed, N failed, N skipped' from meson's test logs (one or more build
directories); exits 1 if anything failed or no test ran."""
import json
import sys

passed = failed = skipped = 0
for build in sys.argv[1:]:
    try:
        with open(build + "/meson-logs/testlog.json") as f:
            for line in f:
                r = json.loads(line).get("result")
                if r == "OK" or r == "EXPECTEDFAIL":
                    passed += 1
                elif r == "SKIP":
                    skipped += 1
                else:
                    failed += 1
    except FileNotFoundError:
        print("no test log in %s" % build, file=sys.stderr)
        failed += 1
print("%d passed, %d failed, %d skipped" % (passed, failed, skipped))
sys.exit(1 if failed or passed == 0 else 0)
