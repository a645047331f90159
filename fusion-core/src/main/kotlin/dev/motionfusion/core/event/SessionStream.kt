/*
 * The streams of a session (docs/SESSION_FORMAT.md): one CSV file each, with its own
 * nanosecond timestamps (SensorEvent.timestamp, the SystemClock.elapsedRealtimeNanos time base)
 * and, for sensor streams, the event's accuracy.
 *
 * Frames: sensor streams in the Android device frame (x right, y up along the screen, z out of
 * the screen); rotation vectors and the fused orientation sensor → East-North-Up (magnetic
 * north). Units: m/s², rad/s, µT, rad; quaternions unitless.
 */
package dev.motionfusion.core.event

/**
 * One stream of a session: its file, its value columns (after `timestamp_ns`) and whether it
 * ends with an `accuracy` column. Declaration order is the replay order of events with equal
 * timestamps: the filter inputs accelerometer and magnetometer, and the references (rotation
 * vectors, truth), come before the gyroscope, so that a gyroscope step, and what it is compared
 * with, use the readings taken at its instant; the live filter's own outputs come last.
 */
public enum class SessionStream(
    /** File name inside the session folder. */
    public val fileName: String,
    /** Names of the value columns, units in the names. */
    public val valueColumns: List<String>,
    /** True when the last column is the SensorEvent accuracy (−1…3). */
    public val hasAccuracy: Boolean,
    /** The Android sensor type constant (Sensor.TYPE_*), 0 for streams that are not a sensor. */
    public val androidType: Int,
) {
    /** TYPE_ACCELEROMETER: specific force, +9.81 on the up axis at rest. */
    ACCELEROMETER("accelerometer.csv", listOf("x_m_s2", "y_m_s2", "z_m_s2"), true, 1),

    /** TYPE_MAGNETIC_FIELD: calibrated (hard-iron corrected) field. */
    MAGNETOMETER("magnetometer.csv", listOf("x_uT", "y_uT", "z_uT"), true, 2),

    /** TYPE_MAGNETIC_FIELD_UNCALIBRATED: values[0..2] raw field, values[3..5] hard-iron bias. */
    MAGNETOMETER_UNCALIBRATED(
        "magnetometer_uncalibrated.csv",
        listOf("x_uT", "y_uT", "z_uT", "bias_x_uT", "bias_y_uT", "bias_z_uT"), true, 14,
    ),

    /** TYPE_GYROSCOPE_UNCALIBRATED: values[0..2] rate without drift compensation, values[3..5] drift. */
    GYROSCOPE_UNCALIBRATED(
        "gyroscope_uncalibrated.csv",
        listOf("x_rad_s", "y_rad_s", "z_rad_s", "bias_x_rad_s", "bias_y_rad_s", "bias_z_rad_s"), true, 16,
    ),

    /**
     * TYPE_ACCELEROMETER_UNCALIBRATED (API 26): values[0..2] specific force without bias
     * compensation, values[3..5] the estimated bias, m/s².
     */
    ACCELEROMETER_UNCALIBRATED(
        "accelerometer_uncalibrated.csv",
        listOf("x_m_s2", "y_m_s2", "z_m_s2", "bias_x_m_s2", "bias_y_m_s2", "bias_z_m_s2"), true, 35,
    ),

    /**
     * TYPE_ROTATION_VECTOR, values as Android gives them: x·sin(θ/2), y·sin(θ/2), z·sin(θ/2),
     * cos(θ/2) (device → ENU), then the estimated heading accuracy in rad (−1 or empty if unknown).
     */
    ROTATION_VECTOR("rotation_vector.csv", listOf("qx", "qy", "qz", "qw", "heading_accuracy_rad"), true, 11),

    /** TYPE_GAME_ROTATION_VECTOR: like the rotation vector without magnetometer; its yaw is arbitrary and drifts. */
    GAME_ROTATION_VECTOR("game_rotation_vector.csv", listOf("qx", "qy", "qz", "qw"), true, 15),

    /** Ground truth (simulations, optical capture): sensor → ENU quaternion. Not written by the app. */
    TRUTH("truth.csv", listOf("qw", "qx", "qy", "qz"), false, 0),

    /** TYPE_GYROSCOPE: calibrated angular rate. */
    GYROSCOPE("gyroscope.csv", listOf("x_rad_s", "y_rad_s", "z_rad_s"), true, 4),

    /** The live Madgwick orientation, sensor → ENU, Hamilton, scalar first, one row per filter step logged. */
    ORIENTATION("orientation.csv", listOf("qw", "qx", "qy", "qz"), false, 0),

    /** Filter diagnostics: gyroscope bias estimate (rad/s, device frame) and the flags 0/1. */
    FILTER_DIAGNOSTICS(
        "filter_diagnostics.csv",
        listOf("bias_x_rad_s", "bias_y_rad_s", "bias_z_rad_s", "at_rest", "magnetic_disturbance", "accelerometer_rejected"),
        false, 0,
    );

    /** Number of value columns. */
    public val valueCount: Int get() = valueColumns.size

    /** The header line, without newline: `timestamp_ns,<values>[,accuracy]`. */
    public val header: String
        get() = (listOf(TIMESTAMP_COLUMN) + valueColumns + (if (hasAccuracy) listOf(ACCURACY_COLUMN) else emptyList())).joinToString(",")

    /** The stream's name in meta.json: the file name without `.csv`. */
    public val key: String get() = fileName.removeSuffix(".csv")

    public companion object {
        public const val TIMESTAMP_COLUMN: String = "timestamp_ns"
        public const val ACCURACY_COLUMN: String = "accuracy"

        /** The stream stored in [fileName], or null. */
        public fun ofFileName(fileName: String): SessionStream? = entries.firstOrNull { it.fileName == fileName }

        /** The stream named [key] in meta.json, or null. */
        public fun ofKey(key: String): SessionStream? = entries.firstOrNull { it.key == key }
    }
}
