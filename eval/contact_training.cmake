# Section 57.6: the training set of the logistic contact probability, simulated physics runs
# (eval/contact_training.hpp), in its own library so that only what trains a model pulls in MuJoCo.
add_library(legkit_contact_training STATIC contact_training.cpp contact_training.hpp)
target_include_directories(legkit_contact_training PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(legkit_contact_training PUBLIC legkit_contact_learned legkit_estimation legkit_physics
                                                     legkit_io legkit_model)
