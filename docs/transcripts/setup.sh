# Sourced by each transcript: the doc's commands run as in a checkout (build/, scenes/, scripts/),
# in cram's own temporary folder, so the files they write go there. RTM_BUILD_DIR: the build
# under test (ctest sets it); the reference cache is the run's own.
root=$(cd "$TESTDIR/../.." && pwd)
ln -s "${RTM_BUILD_DIR:-$root/build}" build
ln -s "$root/scenes" scenes
ln -s "$root/scripts" scripts
export RTM_CACHE_DIR="$CRAMTMP/cache" SYSTEMC_DISABLE_COPYRIGHT_MESSAGE=1
