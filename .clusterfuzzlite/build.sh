#!/bin/bash -eu
# Builds every cargo-fuzz target of geocert for ClusterFuzzLite / OSS-Fuzz (the base image's
# nightly toolchain and sanitizer flags), and puts beside each binary in $OUT its dictionary
# (TARGET.dict) and its committed seed corpus (TARGET_seed_corpus.zip).
cd "$SRC/geocert"
cargo fuzz build -O --debug-assertions
triple="$(rustc -vV | sed -n 's/^host: //p')"
for target in $(cargo fuzz list); do
    cp "fuzz/target/$triple/release/$target" "$OUT/"
    if [ -f "fuzz/dict/$target.dict" ]; then
        cp "fuzz/dict/$target.dict" "$OUT/$target.dict"
    fi
    if compgen -G "fuzz/corpus/$target/seed-*" > /dev/null; then
        zip -q -j "$OUT/${target}_seed_corpus.zip" fuzz/corpus/"$target"/seed-*
    fi
done
