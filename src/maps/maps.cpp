// maps: normal-from-height, cone maps (later issues)
