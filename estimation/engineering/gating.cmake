# Section 57.9: innovation gating and stationary initialisation, in legkit_estimation (every filter gates). Owner: gating.
target_sources(legkit_estimation PRIVATE ${CMAKE_CURRENT_LIST_DIR}/gating.cpp
                                         ${CMAKE_CURRENT_LIST_DIR}/stationary_init.cpp)
