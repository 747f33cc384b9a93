# legkit_contact_learned: the model-based and learned detectors of section 57.6 (the generalized
# momentum observer, the logistic contact probability and its training).
add_library(legkit_contact_learned STATIC
  momentum_observer.cpp
  momentum_observer.hpp
  logistic_contact.cpp
  logistic_contact.hpp
  logistic_training.cpp
  logistic_training.hpp)
target_include_directories(legkit_contact_learned PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_contact_learned PUBLIC legkit_model lie::lie)
