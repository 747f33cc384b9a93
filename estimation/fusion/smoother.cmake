# (owner: smoother) — see estimation/fusion/CMakeLists.txt
