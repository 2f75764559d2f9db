#!/usr/bin/env bash
# Installs the Debian packages the service tests need, only those missing. As root it installs them;
# otherwise it says what is missing and carries on (those tests then skip outside CI, fail in CI).
set -u
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
  echo "system-packages: not root; missing ${missing[*]} (service tests will skip outside CI)" >&2
  exit 0
fi
echo "system-packages: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq >/dev/null && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null \
  || { echo "system-packages: apt-get failed for ${missing[*]}" >&2; exit 1; }
# mosquitto's Debian package starts a system broker on 1883; our tests start their own on free ports.
command -v systemctl >/dev/null && systemctl disable --now mosquitto >/dev/null 2>&1 || true
exit 0
