#!/usr/bin/env bash
# Installs what a fresh Debian machine lacks to build, test and run stoneskip: Mesa's software
# Vulkan/GL drivers (the app and the offscreen renderer run on them without a GPU), Xvfb for the
# window smoke test (with openbox, a real window manager, and xprop for the minimise check), fonts,
# pkg-config and python3 (the import-circle check). Idempotent; skips apt when everything is present.
set -euo pipefail
pkgs=(mesa-vulkan-drivers libvulkan1 libegl1 libgl1-mesa-dri xvfb xauth xdotool imagemagick
      openbox x11-utils libfontconfig1-dev pkg-config fonts-dejavu-core python3-minimal)
missing=()
for p in "${pkgs[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
command -v cargo >/dev/null || { echo "setup: cargo not found: install Rust (rustup)" >&2; exit 1; }
rustup component add rustfmt clippy >/dev/null 2>&1 || true
