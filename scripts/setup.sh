#!/usr/bin/env bash
# Installs what a fresh Debian 12 machine lacks to build, test and run prismrelief.
# Idempotent: packages already present are skipped, so a second run changes nothing.
set -euo pipefail

packages=(
    build-essential cmake ninja-build pkg-config git
    libopenmesh-dev libglm-dev libosmesa6-dev libegl-dev libgles-dev libglfw3-dev
    libstb-dev libcli11-dev nlohmann-json3-dev libfmt-dev libimgui-dev python3-glad
    libgtest-dev
    xvfb xauth xdotool
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "setup: all ${#packages[@]} packages present"
    exit 0
fi

echo "setup: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
