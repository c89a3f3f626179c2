#!/bin/sh
# AUTO-07p's compiled program run directly (no Python start-up): the equilibrium continued in the
# speed until the Hopf point is located (c.hb). Run in a folder where wheelset.exe was built.
cd "$(dirname "$0")" && cp c.hb fort.2 && exec ./wheelset.exe
