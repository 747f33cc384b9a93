# (owner: factors) — see estimation/fusion/CMakeLists.txt
