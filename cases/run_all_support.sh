# Shared by cases/*/run-all (sourced, not run, from the repository root):
#   source cases/run_all_support.sh STUDY SAMPLES "$@"
# reads the size from the run-all's first argument unless it is an option (full: cases/STUDY,
# samples cases/samples/SAMPLES*.prm, results/STUDY; small: cases/STUDY/small,
# small-SAMPLES*, results/STUDY/small) and sets cases, samples and results; the rest of the
# arguments go to trackbed run and build-sample (options, e.g. --threads 2). Its functions build
# missing samples and run unfinished models, resuming either from its checkpoint when an earlier
# call was interrupted (trackbed resume).
study=$1
stem=$2
shift 2
size=full
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
  size=$1
  shift
fi
case "$size" in
  full) cases=cases/$study; samples=$stem; results=results/$study ;;
  small) cases=cases/$study/small; samples=small-$stem; results=results/$study/small ;;
  *) echo "run-all: unknown size '$size'; valid: full, small" >&2; exit 2 ;;
esac
bin=build/cases/trackbed
[ -x "$bin" ] || scripts/build
options=("$@")  # for trackbed run and build-sample, e.g. --threads 2

resume_options=()  # trackbed resume takes --threads alone, of the options given to run-all
for ((i = 0; i < ${#options[@]}; i++)); do
  [ "${options[i]}" = --threads ] && resume_options=(--threads "${options[i + 1]:-}")
done
resume_or() {  # resumes the run or sample build in folder $1 if it holds a checkpoint, else runs the rest
  local folder=$1
  shift
  if [ -f "$folder/checkpoint.h5" ]; then
    echo "run-all: resuming $folder from its checkpoint"
    "$bin" resume "$folder" ${resume_options[@]+"${resume_options[@]}"}
  else
    "$@"
  fi
}
sample() {  # builds results/samples/$1/sample.h5 from cases/samples/$1.prm if missing
  [ -f "results/samples/$1/sample.h5" ] ||
    resume_or "results/samples/$1" "$bin" build-sample "cases/samples/$1.prm" ${options[@]+"${options[@]}"}
}
run_model() {  # runs case file $1/$2.prm into results folder $3/$2 unless it has finished
  if grep -q '"status": "finished"' "$3/$2/summary.json" 2>/dev/null; then
    echo "run-all: $2 already done ($3/$2)"
    return
  fi
  resume_or "$3/$2" "$bin" run "$1/$2.prm" ${options[@]+"${options[@]}"}
}
