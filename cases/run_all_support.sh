# Shared by cases/*/run-all (sourced, not run): builds missing samples and runs unfinished models,
# resuming either from its checkpoint when an earlier call was interrupted (trackbed resume).
# The sourcing script sets bin (the trackbed executable) and options (its extra arguments, e.g.
# --threads 2) before sourcing it.

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
