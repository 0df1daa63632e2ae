#!/bin/sh
# Runs one unit-test command (usually mpiexec ... test_binary) and passes only when it exits 0
# AND printed Teuchos' "End Result: TEST PASSED": a crash or a sanitizer halt after the line
# fails, and so does a binary that exits 0 without running its tests.
log=$(mktemp)
"$@" > "$log" 2>&1
rc=$?
cat "$log"
passed=0
grep -q "End Result: TEST PASSED" "$log" && passed=1
rm -f "$log"
if [ "$rc" -ne 0 ]; then
  echo "run_unit_test.sh: the command exited with $rc"
  exit "$rc"
fi
if [ "$passed" -ne 1 ]; then
  echo "run_unit_test.sh: the command exited 0 but did not print 'End Result: TEST PASSED'"
  exit 1
fi
exit 0
