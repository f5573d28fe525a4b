# Sourced by the bench/lease scripts that run on a lent GPU machine: what each of them did first.
#   O: where the run tool collects files ($OUT; at most 8 come back, so scripts archive into it);
#   W: a scratch folder beside it, with W/r for logs;
#   the carried archives (.carry-cluster/*.tar.xz, from `tools/gpu-run.sh lease`) unpacked, and
#   .carry-cluster/sphbench-other.xz, where carried, as .carry/bin/sphbench-other;
#   X: the command prefix that finds the carried binaries and libraries;
#   W/r/gpu.txt: the GPU's name, clocks, temperature and power as the scripts start.
O=${OUT:-/tmp/out}; W=$(mktemp -d); mkdir -p "$O" "$W/r"
for t in .carry-cluster/*.tar.xz; do [ -f "$t" ] && tar -xJf "$t"; done
if [ -f .carry-cluster/sphbench-other.xz ] && [ -d .carry/bin ]; then
  xz -dc .carry-cluster/sphbench-other.xz > .carry/bin/sphbench-other && chmod +x .carry/bin/sphbench-other
fi
X="tools/gpu-run.sh exec"
nvidia-smi --query-gpu=name,clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv > "$W/r/gpu.txt" 2>&1
