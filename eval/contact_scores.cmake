# Section 57.6: contact detectors scored against the physics' true contact (eval/contact_scores.hpp).
target_sources(legkit_eval PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/contact_scores.cpp)
