# legkit_contact: the sensor-based and kinematic detectors of section 57.6 (gait clock, GRF
# threshold, Schmitt trigger, kinematic, the foot force from joint torques, the fallback chain).
add_library(legkit_contact STATIC
  gait_clock.cpp
  gait_clock.hpp
  foot_force.cpp
  foot_force.hpp
  grf_threshold.cpp
  grf_threshold.hpp
  schmitt_trigger.cpp
  schmitt_trigger.hpp
  kinematic_detector.cpp
  kinematic_detector.hpp
  fallback_detector.cpp
  fallback_detector.hpp)
target_include_directories(legkit_contact PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_contact PUBLIC legkit_model lie::lie)

# legkit_contact_factory: every detector by name (detectors.hpp), above legkit_contact and
# legkit_contact_learned (learned.cmake) so that neither depends on the other.
add_library(legkit_contact_factory STATIC detectors.cpp detectors.hpp)
target_include_directories(legkit_contact_factory PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_contact_factory PUBLIC legkit_contact legkit_contact_learned)
