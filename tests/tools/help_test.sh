#!/usr/bin/env bash
# Every subcommand answers --help with its usage on stdout and exit 0; bad command lines exit 2
# with a message naming the problem.
source "$(dirname "$0")/common.sh"

for cmd in demo replay eval diff check-config; do
  expect_exit 0 "$OUT/$cmd.help" "$MVTRACK" "$cmd" --help
  expect_grep "^usage: mvtrack $cmd" "$OUT/$cmd.help"
  expect_grep "^options:" "$OUT/$cmd.help"
  # An unknown option is a usage error naming the option.
  expect_exit 2 "$OUT/$cmd.bad" "$MVTRACK" "$cmd" --no-such-option
  expect_grep "unknown option --no-such-option" "$OUT/$cmd.bad"
done
for cmd in replay eval diff check-config; do
  expect_grep "Exit status" "$OUT/$cmd.help"
done
# A mistyped option or command gets the closest one suggested.
expect_exit 2 "$OUT/typo_option" "$MVTRACK" replay --calibraton x.yaml in.lcmlog
expect_grep "unknown option --calibraton \(did you mean --calibration\?\)" "$OUT/typo_option"
expect_exit 2 "$OUT/typo_command" "$MVTRACK" replya
expect_grep "unknown command 'replya' \(did you mean 'replay'\?\)" "$OUT/typo_command"

expect_exit 0 "$OUT/top.help" "$MVTRACK" --help
for cmd in replay eval diff check-config; do
  expect_grep "^  $cmd " "$OUT/top.help"
done
expect_exit 2 "$OUT/none" "$MVTRACK"
expect_exit 2 "$OUT/unknown" "$MVTRACK" no-such-command
expect_grep "unknown command 'no-such-command'" "$OUT/unknown"

# Missing required arguments.
expect_exit 2 "$OUT/replay.noargs" "$MVTRACK" replay
expect_grep "missing argument INPUT.lcmlog" "$OUT/replay.noargs"
expect_exit 2 "$OUT/diff.onearg" "$MVTRACK" diff a.jsonl
expect_grep "missing argument B" "$OUT/diff.onearg"
expect_exit 2 "$OUT/check.noargs" "$MVTRACK" check-config
expect_grep "missing argument OPTIONS.yaml" "$OUT/check.noargs"
expect_exit 2 "$OUT/eval.nogt" "$MVTRACK" eval tracks.jsonl
expect_grep "\-\-gt is required" "$OUT/eval.nogt"
echo "ok"
