#!/usr/bin/env bash
# Renders one fixed set of pictures, depth and normal arrays, tile stores, shade rasters,
# simulation frames and meshes with two relief binaries and compares every output byte for
# byte (and the messages, numbers aside): what a refactoring must leave unchanged.
#
#   bench/same_pictures.sh OLD_RELIEF NEW_RELIEF [DIR]
#
# e.g. a release build of the commit before a change against one of the commit after it.
# Prints each output that differs and exits 1 if any does (a tile store's index.json holds
# its build time and differs between any two runs).
set -uo pipefail
old=$(realpath "$1"); new=$(realpath "$2"); dir=${3:-$(mktemp -d)}

render_all() {
    local bin=$1 out=$2
    rm -rf "$out"; mkdir -p "$out"; cd "$out" || exit 2
    run() { local name=$1; shift; "$bin" "$@" >"$name.log" 2>&1; echo "$name $?" >>codes.txt; }
    local s="--size 200x150"
    run default render $s -o default.png --depth default-depth.npy --normals default-normals.npy --fbm-size 256
    run naive render $s -o naive.png --tracer naive --fbm-size 256 --depth naive-depth.npy
    run boxes render $s -o boxes.png --surface boxes --fbm-size 256 --depth boxes-depth.npy
    run safety render $s -o safety.png --tracer safety --no-cache --fbm-size 256 --depth safety-depth.npy
    run hybrid render $s -o hybrid.png --tracer hybrid --fbm-size 256 --depth hybrid-depth.npy
    run hybridlop render $s -o hybridlop.png --tracer hybrid --far lop --show-lop --fbm-size 256
    run clipmap render $s -o clipmap.png --tracer clipmap --fbm-size 256 --depth clipmap-depth.npy
    run ortho render $s -o ortho.png --ortho --view 0,90 --fbm-size 256
    run eye render $s -o eye.png --eye -50,-60,300 --target 128,128,0 --fbm-size 256 --no-shadows
    run gen_fbm generate fbm -o fbm.tif --size 300 --seed 3
    run tif render $s fbm.tif -o tif.png --depth tif-depth.npy
    run tile tile fbm.tif -o store
    run store render $s store -o store.png --depth store-depth.npy
    run store0 render $s store -o store0.png --max-error-px 0
    for scene in arches cave combined; do
        run "gen_$scene" generate mlhm --scene $scene --size 64 -o $scene.json
        for preset in low mid high max; do
            run "${scene}_$preset" render $s $scene.json --preset $preset -o "${scene}_$preset.png" \
                --depth "${scene}_$preset-depth.npy"
        done
        run "${scene}_smooth" render $s $scene.json --mode smooth -o "${scene}_smooth.png" \
            --depth "${scene}_smooth-depth.npy"
        run "${scene}_naive" render $s $scene.json --tracer naive -o "${scene}_naive.png"
    done
    run gen_rr generate mlhm --scene rivers-rain --size 64 -o rr.json
    run rr_mid render $s rr.json -o rr_mid.png
    run sim simulate rr.json --steps 20 -o rr2.json --render-every 10 --frames frames --size 160x120
    run gen_stacks generate stacks -o t.stacks --width 64 --height 48
    run stacks render $s t.stacks -o stacks.png --depth stacks-depth.npy
    run meshmode render $s fbm.tif --mode mesh -o meshmode.png
    run mesh mesh t.stacks -o t.glb
    run shade shade fbm.tif -o shade.tif
    run info info fbm.tif
    run info_mlhm info arches.json
}

(render_all "$old" "$dir/old")
(render_all "$new" "$dir/new")
same=0; differ=0
while IFS= read -r f; do
    if cmp -s "$dir/old/$f" "$dir/new/$f"; then
        same=$((same + 1))
    elif [ "$(basename "$f")" != index.json ]; then
        differ=$((differ + 1)); echo "differs: $f"
    fi
done < <(cd "$dir/old" && find . -type f ! -name '*.log' | sort)
for log in "$dir"/old/*.log; do
    name=$(basename "$log")
    if ! diff -q <(sed -E 's/[0-9]+(\.[0-9]+)?/N/g' "$log") \
        <(sed -E 's/[0-9]+(\.[0-9]+)?/N/g' "$dir/new/$name") >/dev/null; then
        differ=$((differ + 1)); echo "messages differ: $name"
    fi
done
cmp -s "$dir/old/codes.txt" "$dir/new/codes.txt" || { differ=$((differ + 1)); echo "exit codes differ"; }
echo "$same outputs the same byte for byte, $differ differences (in $dir)"
[ "$differ" -eq 0 ]
