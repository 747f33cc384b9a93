# (owner: extero) — see estimation/fusion/CMakeLists.txt
