# Top-level usage.
expect 0 "$BIN" --help
contains "$TMP/out" "usage: volspline"
expect 2 "$BIN"
expect 2 "$BIN" no-such-command
contains "$TMP/err" "unknown command"
expect 0 "$BIN" --version
