# (owner: delayed) — see estimation/fusion/CMakeLists.txt
# Delayed pose updates (section 57.8): the filters' history of snapshots and inputs, a pose applied
# at its stamp and the inputs re-run to now, for the InvariantEkf and the Eskf.
add_library(legkit_fusion_delayed STATIC ${CMAKE_CURRENT_LIST_DIR}/delayed_filter.cpp)
target_include_directories(legkit_fusion_delayed PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_fusion_delayed PUBLIC legkit_invariant_ekf legkit_eskf)
