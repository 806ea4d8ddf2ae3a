#!/bin/sh
# Submits the render array and the merge that waits for it:
#   SCENE=$PWD/snake.xml SPP=64 OUT=$PWD/parts deploy/slurm/submit.sh --array=1-16
# Extra arguments go to the render array's sbatch (e.g. another --array or --partition).
set -eu
here=$(dirname "$0")
array=$(sbatch --parsable "$@" "$here/render.sbatch")
array=${array%%;*}   # "jobid;cluster" on multi-cluster sites
sbatch --dependency="afterok:$array" "$here/merge.sbatch"
echo "render array $array; the merge runs when every task has succeeded"
