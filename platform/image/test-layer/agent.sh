#!/bin/bash
# The boot test's agent in the guest: reads "ID LIMIT BASE64" lines from the virtio serial port
# emboss.agent, runs each decoded command with bash for at most LIMIT seconds, answers with its output ("ID| line") and
# "EMBOSS-AGENT-END ID rc=N". Only in the test's copy of the image (platform/image/boot-test.sh).
port=/dev/virtio-ports/emboss.agent
for _ in $(seq 600); do [ -e "$port" ] && break; modprobe virtio_console 2>/dev/null; sleep 0.1; done
exec 3<>"$port" || exit 1
echo "EMBOSS-AGENT-READY uptime=$(cut -d' ' -f1 /proc/uptime)" >&3
while read -r id limit b64 <&3; do
  [ -n "$b64" ] || continue
  cmd=$(printf '%s' "$b64" | base64 -d 2>/dev/null)
  # The test's own limit: a command it no longer waits for never holds up the next ones.
  out=$(timeout -k 2 "$limit" bash -c "$cmd" 2>&1 < /dev/null)
  rc=$?
  [ -n "$out" ] && printf '%s\n' "$out" | sed "s/^/$id| /" >&3
  echo "EMBOSS-AGENT-END $id rc=$rc" >&3
done
