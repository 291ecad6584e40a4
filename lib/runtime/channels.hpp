// Every LCM channel Tiller uses, in one place. docs/reference/channels.md lists who publishes
// and who listens (test/runtime/channel_table_test.cpp checks it); keep the two in step.
#pragma once

namespace tiller::channels {

inline constexpr const char* kJoystick = "TILLER_JOYSTICK";               // joystick_state_t
inline constexpr const char* kManualDemand = "TILLER_MANUAL_DEMAND";      // manual_demand_t
inline constexpr const char* kManualVelocity = "TILLER_MANUAL_VELOCITY";  // manual_velocity_cmd_t
inline constexpr const char* kMode = "TILLER_MODE";                       // controller_mode_t
inline constexpr const char* kArbitration = "TILLER_ARBITRATION";         // arbitration_t
inline constexpr const char* kArmRequest = "TILLER_ARM_REQUEST";          // arm_request_t
inline constexpr const char* kArmState = "TILLER_ARM_STATE";              // arm_state_t
inline constexpr const char* kPath = "TILLER_PATH";                       // path_t
inline constexpr const char* kMissionCommand = "TILLER_MISSION_COMMAND";  // mission_command_t
inline constexpr const char* kOdometry = "TILLER_ODOMETRY";               // odometry_t
inline constexpr const char* kDatum = "TILLER_DATUM";                     // datum_t
inline constexpr const char* kGroundTruth = "TILLER_GROUND_TRUTH";        // odometry_t
inline constexpr const char* kSimState = "TILLER_SIM_STATE";              // sim_state_t
inline constexpr const char* kVelocitySetpoint = "TILLER_VELOCITY_SETPOINT";  // velocity_setpoint_t
inline constexpr const char* kPathProgress = "TILLER_PATH_PROGRESS";          // path_progress_t
inline constexpr const char* kPathSpeed = "TILLER_PATH_SPEED";                // path_speed_t
inline constexpr const char* kStationTarget = "TILLER_STATION_TARGET";        // station_target_t
inline constexpr const char* kWrenchVelocity = "TILLER_WRENCH_VELOCITY";      // wrench_t
inline constexpr const char* kWrenchStation = "TILLER_WRENCH_STATION";        // wrench_t
inline constexpr const char* kWrenchRov = "TILLER_WRENCH_ROV";                // wrench_t
inline constexpr const char* kWrenchFailsafe = "TILLER_WRENCH_FAILSAFE";      // wrench_t
inline constexpr const char* kPidVelocity = "TILLER_PID_VELOCITY";            // pid_terms_t
inline constexpr const char* kPidStation = "TILLER_PID_STATION";              // pid_terms_t
inline constexpr const char* kAllocationStatus = "TILLER_ALLOCATION_STATUS";  // allocation_status_t
inline constexpr const char* kThrusterCommand = "TILLER_THRUSTER_COMMAND";    // thruster_command_t
inline constexpr const char* kThrusterTest = "TILLER_THRUSTER_TEST";          // thruster_test_t
inline constexpr const char* kEscOutput = "TILLER_ESC_OUTPUT";                // esc_output_t
inline constexpr const char* kEscTelemetry = "TILLER_ESC_TELEMETRY";          // esc_telemetry_t
inline constexpr const char* kEscStatus = "TILLER_ESC_STATUS";                // esc_bus_status_t
// Sensors (a driver's config may name another channel, e.g. for a second pressure sensor).
inline constexpr const char* kGnss = "TILLER_GNSS";                     // gnss_fix_t
inline constexpr const char* kImu = "TILLER_IMU";                       // imu_t
inline constexpr const char* kHeading = "TILLER_HEADING";               // heading_t
inline constexpr const char* kPressure = "TILLER_PRESSURE";             // pressure_t
inline constexpr const char* kPower = "TILLER_POWER";                   // power_t
inline constexpr const char* kLeak = "TILLER_LEAK";                     // leak_t
inline constexpr const char* kDvl = "TILLER_DVL";                       // dvl_t
inline constexpr const char* kVehicleStatus = "TILLER_VEHICLE_STATUS";  // vehicle_status_t
inline constexpr const char* kHeartbeatPrefix = "TILLER_HEARTBEAT_";    // heartbeat_t, + PROCESS

// The default LCM URL: multicast with TTL 0, so nothing leaves the host.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

}  // namespace tiller::channels
