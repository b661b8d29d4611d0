#!/usr/bin/env bash
# Runs gui_progressive_refinement.py in the ParaView GUI connected to a pvserver on 127.0.0.1:
# the GUI's idle refinement must accumulate the frames on the server. Usage (ctest does this,
# under Xvfb, with PTV_PLUGIN, PTV_CACHE_DIR, PTV_TEST_TEMP and PYTHONPATH set):
#   gui_clientserver.sh <paraview> <pvserver> <gui_progressive_refinement.py>
# PTV_SERVER_RANKS=N (> 1) starts the server as `mpirun -np N pvserver` (the ranks trace each
# frame together; with PTV_SERVER_SPLIT=1 the script splits the volume across them). Fails when
# the GUI test fails or the server logs an error or warning.
set -u
paraview="$1" pvserver="$2" script="$3"
ranks="${PTV_SERVER_RANKS:-1}"
log="${PTV_TEST_TEMP:-.}/gui_clientserver_pvserver_${ranks}${PTV_SERVER_SPLIT:+_split}.log"
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
launch=()
((ranks > 1)) && launch=(mpirun --allow-run-as-root --oversubscribe -np "$ranks")
"${launch[@]}" "$pvserver" --server-port="$port" --hostname=127.0.0.1 --force-offscreen-rendering > "$log" 2>&1 &
server=$!
for _ in $(seq 300); do
  grep -q "Accepting connection" "$log" && break
  kill -0 "$server" 2> /dev/null || break
  sleep 0.2
done
"$paraview" --dr --server-url="cs://127.0.0.1:$port" --script="$script"
rc=$?
# The server exits when the client disconnects; stop it if it does not.
for _ in $(seq 50); do kill -0 "$server" 2> /dev/null || break; sleep 0.2; done
kill "$server" 2> /dev/null && wait "$server" 2> /dev/null
# The GUI test ends with os._exit (the GUI has no Python quit), so the server sees the socket
# close abruptly: those two socket messages are expected, anything else fails.
if grep -E "ERR\||WARN\||ERROR: In|Warning: In" "$log" |
    grep -v -E "Signal: SIGTERM|Could not receive tag|Some error in socket processing"; then
  echo "pvserver logged errors or warnings (above; $log)"
  rc=1
fi
echo "gui_clientserver.sh: exit code $rc"
exit $rc
