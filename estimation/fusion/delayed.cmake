# (owner: delayed) — see estimation/fusion/CMakeLists.txt
