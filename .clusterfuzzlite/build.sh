#!/bin/bash -eu
# Builds every cargo-fuzz target of geocert for ClusterFuzzLite / OSS-Fuzz (the base image's
# nightly toolchain and sanitizer flags), and puts beside each binary in $OUT its dictionary
# (TARGET.dict) and its committed seed corpus (TARGET_seed_corpus.zip).
# As in fuzz/run-all: the readers of text formats (targets with a dictionary) keep comparison
# tracing; the differential targets, which spend their time in big-integer arithmetic, are
# built without it (about 3x the executions per second) into their own target directory.
cd "$SRC/geocert"
cargo fuzz build -O --debug-assertions
cargo fuzz build -O --debug-assertions --no-trace-compares --target-dir fuzz/target-numeric
triple="$(rustc -vV | sed -n 's/^host: //p')"
for target in $(cargo fuzz list); do
    if [ -f "fuzz/dict/$target.dict" ]; then
        cp "fuzz/target/$triple/release/$target" "$OUT/"
    else
        cp "fuzz/target-numeric/$triple/release/$target" "$OUT/"
    fi
    if [ -f "fuzz/dict/$target.dict" ]; then
        cp "fuzz/dict/$target.dict" "$OUT/$target.dict"
    fi
    if compgen -G "fuzz/corpus/$target/seed-*" > /dev/null; then
        zip -q -j "$OUT/${target}_seed_corpus.zip" fuzz/corpus/"$target"/seed-*
    fi
done
