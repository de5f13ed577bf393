#!/usr/bin/env bash
# Installs what the explorer's tests need on a fresh Debian machine: the software Vulkan driver
# (lavapipe) that egui_kittest renders with, and Xvfb, ImageMagick and xdotool for the real-window
# smoke test. Skips packages already present. Needs root (or sudo).
set -euo pipefail
pkgs=(xvfb xauth mesa-vulkan-drivers libvulkan1 libgl1-mesa-dri libegl1 libegl-mesa0
      libxkbcommon-x11-0 libxcursor1 libxrandr2 libxi6 libx11-xcb1 libwayland-client0
      imagemagick xdotool)
missing=()
for p in "${pkgs[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo=""
[ "$(id -u)" -ne 0 ] && sudo=sudo
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q >/dev/null
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
echo "installed: ${missing[*]}"
