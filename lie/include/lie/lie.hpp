// Everything in lie/: SO(3), SE(3), SE_K(3) (fixed or run-time K) and the IMU error dynamics.
#pragma once

#include "lie/errors.hpp"
#include "lie/imu_dynamics.hpp"
#include "lie/sek3.hpp"
#include "lie/so3.hpp"
#include "lie/so3_series.hpp"
