#!/usr/bin/env bash
# A one-node Slurm cluster for tests (issue 19), started without systemd in a folder of its own:
#   source one_node_slurm.sh; slurm_start DIR [CPUS] && ...; slurm_stop
# slurm_start exports SLURM_CONF, so sbatch, squeue and scontrol talk to this cluster. It returns 77
# (after printing why) when Slurm or munge is not installed and cannot be installed.
# What the set-up needs on these machines (found by trying; see issue 19):
# - cgroup process tracking fails here silently (steps die, the node drains, the batch job still
#   reads COMPLETED): proctrack/linuxproc, task/none, jobacct_gather/none; tests check job outputs;
# - munged wants its socket folder and every parent world-executable, a key of mode 600, and
#   --origin=127.0.0.1 where the hostname does not resolve; Slurm needs NodeAddr=127.0.0.1 and
#   SlurmctldHost=<short hostname>(127.0.0.1), slurmd -N <node name>;
# - batch_sched_delay=0,sched_min_interval=0 remove 3-second gaps between array waves;
#   config_overrides lets the declared CPUs count on a smaller machine;
# - no accounting database: poll squeue until the jobs leave, then `scontrol -o show job`.
# Ports are chosen free, so two test runs can coexist; everything stops by PID file.

slurm_have_tools() {
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v sbatch >/dev/null &&
    command -v munged >/dev/null && command -v mungekey >/dev/null
}

slurm_install() {
  slurm_have_tools && return 0
  if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      slurmctld slurmd slurm-client munge >/dev/null 2>&1 || true
  fi
  slurm_have_tools
}

slurm_free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

slurm_start() {
  SLURM_DIR="$1"
  local cpus="${2:-4}"
  if ! slurm_install; then
    echo "SKIP: slurmctld, slurmd, sbatch or munged is missing and could not be installed" >&2
    return 77
  fi
  mkdir -p "$SLURM_DIR"/{munge,state,spool,log}
  # munged checks the socket folder and each parent: all must be world-executable.
  local d="$SLURM_DIR"
  while [ "$d" != "/" ]; do
    chmod o+x "$d" 2>/dev/null || true
    d="$(dirname "$d")"
  done
  chmod 755 "$SLURM_DIR/munge"
  mungekey --create --keyfile="$SLURM_DIR/munge/munge.key" --force >/dev/null 2>&1
  chmod 600 "$SLURM_DIR/munge/munge.key"
  munged --force --key-file="$SLURM_DIR/munge/munge.key" \
    --socket="$SLURM_DIR/munge/munge.socket" --pid-file="$SLURM_DIR/munge/munged.pid" \
    --log-file="$SLURM_DIR/log/munged.log" --seed-file="$SLURM_DIR/munge/munge.seed" \
    --origin=127.0.0.1 || { echo "munged did not start" >&2; return 1; }

  local host ctld_port slurmd_port
  host="$(hostname -s)"
  ctld_port="$(slurm_free_port)"
  slurmd_port="$(slurm_free_port)"
  SLURM_NODE="aoevalnode$$"
  cat >"$SLURM_DIR/slurm.conf" <<CONF
ClusterName=aoevaltest
SlurmctldHost=${host}(127.0.0.1)
SlurmctldPort=${ctld_port}
SlurmdPort=${slurmd_port}
SlurmUser=$(id -un)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${SLURM_DIR}/munge/munge.socket
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
SlurmdParameters=config_overrides
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
StateSaveLocation=${SLURM_DIR}/state
SlurmdSpoolDir=${SLURM_DIR}/spool
SlurmctldPidFile=${SLURM_DIR}/slurmctld.pid
SlurmdPidFile=${SLURM_DIR}/slurmd.pid
SlurmctldLogFile=${SLURM_DIR}/log/slurmctld.log
SlurmdLogFile=${SLURM_DIR}/log/slurmd.log
MinJobAge=300
NodeName=${SLURM_NODE} NodeAddr=127.0.0.1 CPUs=${cpus} State=UNKNOWN
PartitionName=aoeval Nodes=${SLURM_NODE} Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$SLURM_DIR/slurm.conf"
  slurmctld -f "$SLURM_CONF" -c || { echo "slurmctld did not start" >&2; return 1; }
  slurmd -f "$SLURM_CONF" -N "$SLURM_NODE" || { echo "slurmd did not start" >&2; return 1; }
  local i
  for i in $(seq 1 100); do
    if sinfo -h -N -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then return 0; fi
    sleep 0.1
  done
  echo "the Slurm node did not become idle:" >&2
  sinfo -N >&2 || true
  tail -5 "$SLURM_DIR/log/slurmctld.log" "$SLURM_DIR/log/slurmd.log" >&2 || true
  return 1
}

# Waits (at most $2 seconds, default 120) until none of the job ids in $1 (comma-separated) is
# queued or running.
slurm_wait() {
  local ids="$1" limit="${2:-120}" i
  for i in $(seq 1 $((limit * 10))); do
    [ -z "$(squeue -h -j "$ids" -o '%i' 2>/dev/null)" ] && return 0
    sleep 0.1
  done
  echo "jobs $ids still queued after ${limit} s:" >&2
  squeue >&2 || true
  return 1
}

# The JobState of a finished job (for an array, every task's, one a line).
slurm_job_state() {
  scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p'
}

slurm_stop() {
  [ -n "${SLURM_DIR:-}" ] || return 0
  scancel --quiet --user="$(id -un)" 2>/dev/null || true
  local f pid
  for f in "$SLURM_DIR/slurmd.pid" "$SLURM_DIR/slurmctld.pid" "$SLURM_DIR/munge/munged.pid"; do
    [ -s "$f" ] || continue
    pid="$(cat "$f")"
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  done
  # Leftover step daemons of this cluster: those whose environment names this SLURM_CONF.
  for f in /proc/[0-9]*/environ; do
    pid="${f#/proc/}"
    pid="${pid%/environ}"
    { tr '\0' '\n' <"$f" | grep -qxF "SLURM_CONF=$SLURM_DIR/slurm.conf"; } 2>/dev/null || continue
    grep -q '^slurmstepd' "/proc/$pid/cmdline" 2>/dev/null && kill "$pid" 2>/dev/null || true
  done
}
