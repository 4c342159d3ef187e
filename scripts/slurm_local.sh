#!/usr/bin/env bash
# slurm_local.sh - a throw-away, single-node Slurm cluster for integration tests.
#
# Uses Debian 12's packages (Slurm 22.05, MUNGE 0.5.15) and no systemd: every daemon is
# started by hand, with its configuration, state, spool, sockets, pid files and logs all
# under one directory DIR, so several clusters (one per test) can coexist on one machine and
# nothing under /etc/slurm, /etc/munge, /run or /var is read or written.
#
# Usage:
#   scripts/slurm_local.sh install          # apt-get the packages (no-op when installed)
#   eval "$(scripts/slurm_local.sh start DIR)"   # start munged, slurmctld, slurmd; prints
#                                                # `export SLURM_CONF=...` lines on stdout
#   scripts/slurm_local.sh status DIR       # which daemons run; sinfo/squeue when up
#   scripts/slurm_local.sh stop DIR         # cancel jobs, stop the three daemons
#
# Only the `export` lines go to stdout; progress and errors go to stderr. On failure the
# relevant log lines are printed and the exit status is non-zero.
#
# Environment knobs:
#   SLURM_LOCAL_START_TIMEOUT  seconds to wait for the node to become idle (default 60)
#   SLURM_LOCAL_STOP_TIMEOUT   seconds to wait for each daemon to exit (default 15)
#
# The daemons run as the invoking user. As root (the supported case) SlurmUser and
# SlurmdUser are root and jobs run as the submitting user. Job steps need root to switch
# users, so a non-root caller can only run its own jobs (and may hit permission errors).
set -euo pipefail

readonly PACKAGES=(munge slurm-client slurmctld slurmd)
START_TIMEOUT="${SLURM_LOCAL_START_TIMEOUT:-60}"
STOP_TIMEOUT="${SLURM_LOCAL_STOP_TIMEOUT:-15}"

# Log lines that every healthy start produces: the optional PMIx library is not installed
# (mpi/pmix plugins fail to load; harmless unless jobs use --mpi=pmix), a fresh state folder
# has no state files, and munged notes root decoding credentials meant for SlurmUser.
readonly NOISE='pmix|MPI: Cannot create context|Could not open [a-z]+ state file|Trying backup state|No [a-z]+ state file|Unauthorized credential for client UID=0'

log() { printf 'slurm_local: %s\n' "$*" >&2; }
die() { log "error: $*"; exit 1; }

usage() {
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
}

# ---------------------------------------------------------------------------------------
# install
# ---------------------------------------------------------------------------------------
cmd_install() {
  local missing=() p
  for p in "${PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -eq 0 ]; then
    log "packages already installed: ${PACKAGES[*]}"
    return 0
  fi
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  log "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  # The maintainer scripts try to start the services through invoke-rc.d; without an init
  # system (or with a policy-rc.d that forbids it) that is refused, harmlessly. They also
  # create /etc/munge/munge.key, which this script does not use.
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# ---------------------------------------------------------------------------------------
# helpers shared by start/stop/status
# ---------------------------------------------------------------------------------------

# Resolves DIR to an absolute path and sets the global path variables used below.
set_paths() {
  if [ $# -lt 1 ] || [ -z "$1" ]; then die "missing DIR argument"; fi
  mkdir -p "$1"
  D="$(cd "$1" && pwd -P)"
  # slurm.conf values cannot hold whitespace, and '#' starts a comment there.
  case "$D" in
    *[[:space:]#]*) die "DIR must not contain whitespace or '#': $D" ;;
  esac
  CONF="$D/etc/slurm.conf"
  MUNGE_DIR="$D/munge"
  MUNGE_KEY="$MUNGE_DIR/munge.key"
  MUNGE_SOCKET="$MUNGE_DIR/munge.socket.2"
  MUNGED_PID="$D/run/munged.pid"
  SLURMCTLD_PID="$D/run/slurmctld.pid"
  SLURMD_PID="$D/run/slurmd.pid"
  MUNGED_LOG="$D/log/munged.log"
  SLURMCTLD_LOG="$D/log/slurmctld.log"
  SLURMD_LOG="$D/log/slurmd.log"
}

# Prints the pid recorded in pid file $1 when that process is alive and really is the
# daemon we started: its command line must name program $2 and mention string $3 (the
# slurm.conf or munge socket of this DIR). Never trusts a stale pid that got reused.
live_pid() {
  local pidfile="$1" prog="$2" marker="$3" pid cmdline
  [ -s "$pidfile" ] || return 1
  pid="$(tr -dc '0-9' <"$pidfile")"
  [ -n "$pid" ] && [ -r "/proc/$pid/cmdline" ] || return 1
  cmdline="$(tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null)" || return 1
  case "$cmdline" in
    *"$prog"*"$marker"*) printf '%s\n' "$pid" ;;
    *) return 1 ;;
  esac
}

munged_pid() { live_pid "$MUNGED_PID" munged "$MUNGE_SOCKET"; }
slurmctld_pid() { live_pid "$SLURMCTLD_PID" slurmctld "$CONF"; }
slurmd_pid() { live_pid "$SLURMD_PID" slurmd "$CONF"; }

# Prints the last lines of the given log files (those that exist) to stderr, without the
# messages every healthy start logs too (see NOISE).
show_logs() {
  local f
  for f in "$@"; do
    if [ -s "$f" ]; then
      log "---- last lines of $f (without routine messages) ----"
      grep -Ev "$NOISE" "$f" | tail -n 25 >&2 || true
    else
      log "---- $f: missing or empty ----"
    fi
  done
}

# True when TCP port $1 has a listener (IPv4 or IPv6). Reads /proc/net so it needs no
# iproute2/net-tools; state 0A is LISTEN.
port_in_use() {
  local hex
  hex="$(printf '%04X' "$1")"
  awk -v p=":$hex" 'NR > 1 && $4 == "0A" && substr($2, length($2) - 4) == p { f = 1 }
                    END { exit !f }' /proc/net/tcp /proc/net/tcp6 2>/dev/null
}

# Prints a free TCP port; $1 is a port to skip (so two calls give two ports). Starts at a
# random point of 20000-59999 so that parallel clusters are unlikely to pick the same one.
free_port() {
  local skip="${1:-0}" p i
  p=$((20000 + (RANDOM * 32768 + RANDOM) % 40000))
  for ((i = 0; i < 200; i++)); do
    if [ "$p" -ne "$skip" ] && ! port_in_use "$p"; then
      printf '%s\n' "$p"
      return 0
    fi
    p=$((p + 1))
    if [ "$p" -ge 60000 ]; then p=20000; fi
  done
  die "no free TCP port found"
}

# Sends SIGTERM to the pids given as NAME:PID words, waits up to STOP_TIMEOUT s for all
# of them, then SIGKILLs whatever is left. Several at once, since each takes 1-2 s to exit.
stop_pids() {
  local w pid i alive
  for w in "$@"; do
    log "stopping ${w%%:*} (pid ${w#*:})"
    kill -TERM "${w#*:}" 2>/dev/null || true
  done
  for ((i = 0; i < STOP_TIMEOUT * 10; i++)); do
    alive=0
    for w in "$@"; do
      if kill -0 "${w#*:}" 2>/dev/null; then alive=1; fi
    done
    if [ "$alive" -eq 0 ]; then return 0; fi
    sleep 0.1
  done
  for w in "$@"; do
    pid="${w#*:}"
    if kill -0 "$pid" 2>/dev/null; then
      log "${w%%:*} (pid $pid) ignored SIGTERM for ${STOP_TIMEOUT}s; sending SIGKILL"
      kill -KILL "$pid" 2>/dev/null || true
    fi
  done
  sleep 0.2
}

# Runs a Slurm client against this cluster, bounded in time.
sl() { SLURM_CONF="$CONF" timeout 20 "$@"; }

# ---------------------------------------------------------------------------------------
# start
# ---------------------------------------------------------------------------------------

# Writes $CONF. Every path is under $D; see the comments in the file for each setting.
write_conf() {
  local host="$1" ctld_port="$2" slurmd_port="$3" cpus mem_mib margin
  cpus="$(nproc)"
  # RealMemory must not exceed what slurmd measures, or the node is drained as "Low
  # RealMemory": MemTotal minus 5 % (at least 256 MiB) leaves room for rounding.
  mem_mib=$(($(awk '/^MemTotal:/ { print $2 }' /proc/meminfo) / 1024))
  margin=$((mem_mib / 20))
  if [ "$margin" -lt 256 ]; then margin=256; fi
  mem_mib=$((mem_mib - margin))
  if [ "$mem_mib" -lt 1 ]; then mem_mib=1; fi

  # No cgroup.conf is written: none of the plugins chosen below uses cgroups.
  cat >"$CONF" <<EOF
# Generated by scripts/slurm_local.sh for a single-node test cluster. Do not edit: it is
# rewritten on every start.
ClusterName=corridorsim
# Short hostname as slurmctld sees it, plus the address to reach it: clients and slurmd
# connect to 127.0.0.1 and never need the hostname to resolve.
SlurmctldHost=${host}(127.0.0.1)
# Free ports picked at start, so several clusters (and a system Slurm) can coexist.
SlurmctldPort=${ctld_port}
SlurmdPort=${slurmd_port}
# Daemons run as the caller (root in the supported case); jobs run as the submitting user.
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
# MUNGE authentication through this cluster's own munged socket.
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${MUNGE_SOCKET}
# All state, spool, pid and log files under ${D}.
StateSaveLocation=${D}/state
SlurmdSpoolDir=${D}/spool
SlurmctldPidFile=${SLURMCTLD_PID}
SlurmdPidFile=${SLURMD_PID}
SlurmctldLogFile=${SLURMCTLD_LOG}
SlurmdLogFile=${SLURMD_LOG}
SlurmctldDebug=info
SlurmdDebug=info
# Empty SPANK config instead of /etc/slurm/plugstack.conf.
PlugStackConfig=${D}/etc/plugstack.conf
# No cgroups (the default proctrack/cgroup depends on the host's cgroup mounts, which
# vary between containers and VMs): track job processes by parent pid; no task binding;
# no accounting or job completion records (these four are the defaults, stated for clarity).
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
# Schedule individual CPUs (default select/linear hands out whole nodes), so array tasks
# run side by side; memory is not a consumable resource.
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
# Start batch jobs (and jobs whose dependency just got satisfied) at the next 1 s tick
# of the scheduler instead of in the default 3 s batches (smoke test: ~2 s instead of ~6 s).
SchedulerParameters=batch_sched_delay=0
# No mail program on the box; default /bin/mail would only produce errors.
MailProg=/bin/true
# A node that was DOWN (e.g. the previous slurmd was killed) rejoins when it registers.
ReturnToService=2
# Trust the node line below instead of draining the node when the hardware differs
# slightly (e.g. a container reporting more cores or memory than nproc/MemTotal).
SlurmdParameters=config_overrides
# Finished jobs stay visible to squeue/scontrol for 5 minutes (the default; tests that
# check JobState with scontrol rely on it).
MinJobAge=300
NodeName=${host} NodeAddr=127.0.0.1 NodeHostname=${host} CPUs=${cpus} RealMemory=${mem_mib} State=UNKNOWN
PartitionName=debug Nodes=${host} Default=YES MaxTime=INFINITE State=UP
EOF
  : >"$D/etc/plugstack.conf"
}

start_munged() {
  if munged_pid >/dev/null; then
    log "munged already running"
    return 0
  fi
  # munged insists that the socket's folder is searchable by all (o+x) and writable by no
  # one but its owner, and that the key is readable by no one but its owner.
  chmod 0755 "$MUNGE_DIR"
  # That check covers every ancestor folder, too. mktemp -d makes DIR 0700, so DIR gets
  # a+x (search only; listing stays private). Above DIR we change nothing: if an ancestor
  # lacks o+x (e.g. a 0700 home), munged runs with --force, turning the error into a warning.
  local force=() dir
  chmod a+x "$D"
  dir="$D"
  while [ "$dir" != / ]; do
    dir="$(dirname "$dir")"
    if [ "$(($(stat -c '%#a' "$dir") & 1))" -eq 0 ]; then
      log "$dir is not searchable by others; starting munged with --force"
      force=(--force)
      break
    fi
  done
  if [ ! -s "$MUNGE_KEY" ]; then
    log "creating munge key $MUNGE_KEY"
    mungekey --create --keyfile="$MUNGE_KEY" 2>/dev/null ||
      (umask 077 && dd if=/dev/urandom of="$MUNGE_KEY" bs=1024 count=1 status=none)
  fi
  chmod 0400 "$MUNGE_KEY"
  rm -f "$MUNGE_SOCKET" "$MUNGE_SOCKET.lock" # stale leftovers of a killed munged
  log "starting munged"
  if ! munged "${force[@]}" --key-file="$MUNGE_KEY" --socket="$MUNGE_SOCKET" --pid-file="$MUNGED_PID" \
    --log-file="$MUNGED_LOG" --seed-file="$MUNGE_DIR/munged.seed" 2>>"$MUNGED_LOG"; then
    show_logs "$MUNGED_LOG"
    die "munged failed to start"
  fi
  # Round trip a credential to be sure the socket works.
  local i
  for ((i = 0; i < 50; i++)); do
    if munge -n -S "$MUNGE_SOCKET" 2>/dev/null | unmunge -S "$MUNGE_SOCKET" >/dev/null 2>&1; then
      return 0
    fi
    sleep 0.1
  done
  show_logs "$MUNGED_LOG"
  die "munged started but credentials do not round-trip through $MUNGE_SOCKET"
}

# Starts daemon $1 (slurmctld|slurmd) unless running; waits (10 s at most) for its pid file.
start_slurm_daemon() {
  local name="$1" logf pidf i
  if "${name}_pid" >/dev/null; then
    log "$name already running"
    return 0
  fi
  if [ "$name" = slurmctld ]; then logf="$SLURMCTLD_LOG" pidf="$SLURMCTLD_PID"; else
    logf="$SLURMD_LOG" pidf="$SLURMD_PID"
  fi
  rm -f "$pidf"
  log "starting $name"
  # Both daemonize; their stderr before that goes to the log too (e.g. config errors).
  if ! SLURM_CONF="$CONF" "$name" -f "$CONF" 2>>"$logf"; then
    show_logs "$logf"
    die "$name failed to start"
  fi
  # The pid file appears once the daemon is past configuration and plugin loading.
  for ((i = 0; i < 100; i++)); do
    if "${name}_pid" >/dev/null; then break; fi
    sleep 0.1
  done
  if ! "${name}_pid" >/dev/null; then
    show_logs "$logf"
    die "$name did not come up (no live pid in $pidf)"
  fi
}

# EXIT trap of cmd_start: a start that fails stops the daemons of its DIR again.
stop_on_failed_start() {
  local rc=$?
  if [ "$rc" -ne 0 ]; then cmd_stop "$D" || true; fi
  exit "$rc"
}

cmd_start() {
  set_paths "$@"
  local host i state
  # die() below exits non-zero; then stop what runs of this DIR, so that a failed start
  # leaves no half-started cluster behind (the logs stay in DIR/log).
  trap stop_on_failed_start EXIT
  for i in munged slurmctld slurmd; do
    command -v "$i" >/dev/null || die "$i not found; run: $0 install"
  done
  # Unix socket paths are limited to 108 bytes; slurmd's step sockets live in the spool
  # folder and are named NODE_JOBID.STEPID, so keep DIR short (e.g. mktemp -d).
  if [ "${#D}" -gt 80 ]; then die "DIR path too long for unix sockets (${#D} > 80): $D"; fi
  mkdir -p "$D"/{etc,state,spool,log,run} "$MUNGE_DIR"
  chmod 0755 "$D"/{etc,state,spool,log,run}

  # Short hostname: what slurmctld compares SlurmctldHost with and what slurmd uses as its
  # node name. uname -n needs no name resolution.
  host="$(uname -n)"
  host="${host%%.*}"

  if slurmctld_pid >/dev/null || slurmd_pid >/dev/null; then
    log "cluster in $D is already (partly) running; keeping its slurm.conf"
    [ -s "$CONF" ] || die "daemons running but $CONF is missing"
  else
    local ctld_port
    ctld_port="$(free_port)"
    write_conf "$host" "$ctld_port" "$(free_port "$ctld_port")"
  fi

  start_munged
  start_slurm_daemon slurmctld
  start_slurm_daemon slurmd

  # Wait until the node has registered and is idle (or mixed/allocated when jobs that
  # survived in the state folder run already).
  log "waiting up to ${START_TIMEOUT}s for node $host to become idle"
  local deadline=$((SECONDS + START_TIMEOUT))
  state=""
  while [ "$SECONDS" -lt "$deadline" ]; do
    for i in slurmctld slurmd munged; do
      if ! "${i}_pid" >/dev/null; then
        show_logs "$SLURMCTLD_LOG" "$SLURMD_LOG" "$MUNGED_LOG"
        die "$i exited during start-up"
      fi
    done
    state="$(sl sinfo -h -N -n "$host" -o '%T' 2>/dev/null | head -n 1 || true)"
    case "$state" in
      idle | mixed | allocated | completing) break ;;
    esac
    sleep 0.5
  done
  case "$state" in
    idle | mixed | allocated | completing) ;;
    *)
      log "node state: '${state:-<no answer from slurmctld>}'"
      sl sinfo -R >&2 2>/dev/null || true
      show_logs "$SLURMCTLD_LOG" "$SLURMD_LOG" "$MUNGED_LOG"
      die "node $host did not become idle within ${START_TIMEOUT}s"
      ;;
  esac
  log "cluster up in $D (node $host: $state)"
  trap - EXIT

  # For the caller to eval. Clients only need SLURM_CONF: the munge socket is in AuthInfo.
  printf 'export SLURM_CONF=%q\n' "$CONF"
  printf 'export SLURM_LOCAL_DIR=%q\n' "$D"
  printf 'export SLURM_LOCAL_MUNGE_SOCKET=%q\n' "$MUNGE_SOCKET"
}

# ---------------------------------------------------------------------------------------
# stop
# ---------------------------------------------------------------------------------------
cmd_stop() {
  set_paths "$@"
  local pid i
  # Cancel jobs first so that their slurmstepd processes (not children of slurmd) exit too.
  if slurmctld_pid >/dev/null && slurmd_pid >/dev/null; then
    local jobs
    jobs="$(sl squeue -h -t PD,R,CG,S -o '%A' 2>/dev/null | tr '\n' ' ' || true)"
    if [ -n "${jobs// /}" ]; then
      log "cancelling jobs: $jobs"
      # shellcheck disable=SC2086 # word splitting of the job list is intended
      sl scancel $jobs 2>/dev/null || true
      for ((i = 0; i < STOP_TIMEOUT * 2; i++)); do
        [ -z "$(sl squeue -h -t R,CG -o '%A' 2>/dev/null || true)" ] && break
        sleep 0.5
      done
    fi
  fi
  # slurmd first, so that it does not outlive its controller and log connection errors;
  # then slurmctld (saves its state, which needs no munge) and munged together.
  if pid="$(slurmd_pid)"; then stop_pids "slurmd:$pid"; fi
  local rest=()
  if pid="$(slurmctld_pid)"; then rest+=("slurmctld:$pid"); fi
  if pid="$(munged_pid)"; then rest+=("munged:$pid"); fi
  if [ ${#rest[@]} -gt 0 ]; then stop_pids "${rest[@]}"; fi
  local left=""
  slurmd_pid >/dev/null && left+=" slurmd"
  slurmctld_pid >/dev/null && left+=" slurmctld"
  munged_pid >/dev/null && left+=" munged"
  if [ -n "$left" ]; then die "still running:$left"; fi
  rm -f "$SLURMD_PID" "$SLURMCTLD_PID" "$MUNGED_PID"
  log "cluster in $D stopped"
}

# ---------------------------------------------------------------------------------------
# status: exit 0 when all three daemons run, 3 when none, 1 when only some do.
# ---------------------------------------------------------------------------------------
cmd_status() {
  if [ $# -lt 1 ] || [ ! -d "$1" ]; then die "no such DIR: ${1:-<none>}"; fi
  set_paths "$@"
  local name pid up=0
  for name in munged slurmctld slurmd; do
    if pid="$("${name}_pid")"; then
      printf '%-10s running (pid %s)\n' "$name" "$pid"
      up=$((up + 1))
    else
      printf '%-10s stopped\n' "$name"
    fi
  done
  if slurmctld_pid >/dev/null; then
    printf 'SLURM_CONF=%s\n' "$CONF"
    sl sinfo || true
    sl squeue || true
  fi
  if [ "$up" -eq 3 ]; then return 0; fi
  if [ "$up" -eq 0 ]; then return 3; fi
  return 1
}

main() {
  [ $# -ge 1 ] || usage
  local sub="$1"
  shift
  case "$sub" in
    install) cmd_install ;;
    start) cmd_start "$@" ;;
    stop) cmd_stop "$@" ;;
    status) cmd_status "$@" ;;
    -h | --help | help) usage ;;
    *) log "unknown subcommand: $sub"; usage ;;
  esac
}

main "$@"
