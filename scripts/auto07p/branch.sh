#!/bin/sh
# AUTO-07p's compiled program run directly (no Python start-up), what scripts/auto07p-time times:
# the equilibrium continued to the Hopf point (c.hb), then the periodic orbits to max y = 8 mm
# (c.time.po). Run in a folder where wheelset.exe was built (scripts/auto07p-time does it).
cd "$(dirname "$0")" && cp c.hb fort.2 && ./wheelset.exe > /dev/null && mv fort.8 fort.3 \
  && cp c.time.po fort.2 && exec ./wheelset.exe
