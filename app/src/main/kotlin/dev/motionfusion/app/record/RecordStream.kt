package dev.motionfusion.app.record

import android.hardware.Sensor

/**
 * The raw sensor streams a recording holds, with the Android sensor type and the number of
 * `SensorEvent.values` entries kept (device frame, SI units as Android gives them):
 * - ACCELEROMETER m/s² x, y, z (with gravity); GYROSCOPE rad/s; MAGNETOMETER µT;
 * - GYROSCOPE_UNCALIBRATED rad/s x, y, z then the estimated drift x, y, z;
 * - MAGNETOMETER_UNCALIBRATED µT x, y, z then the hard-iron bias x, y, z;
 * - ROTATION_VECTOR x·sin(θ/2), y·sin(θ/2), z·sin(θ/2), cos(θ/2), heading accuracy (rad, −1 unknown);
 * - GAME_ROTATION_VECTOR the same four without heading accuracy.
 * Missing trailing values (older devices give rotation vectors with 3 or 4 entries) are NaN.
 */
internal enum class RecordStream(val androidType: Int, val valueCount: Int) {
    ACCELEROMETER(Sensor.TYPE_ACCELEROMETER, 3),
    GYROSCOPE(Sensor.TYPE_GYROSCOPE, 3),
    MAGNETOMETER(Sensor.TYPE_MAGNETIC_FIELD, 3),
    GYROSCOPE_UNCALIBRATED(Sensor.TYPE_GYROSCOPE_UNCALIBRATED, 6),
    MAGNETOMETER_UNCALIBRATED(Sensor.TYPE_MAGNETIC_FIELD_UNCALIBRATED, 6),
    ROTATION_VECTOR(Sensor.TYPE_ROTATION_VECTOR, 5),
    GAME_ROTATION_VECTOR(Sensor.TYPE_GAME_ROTATION_VECTOR, 4),
    ;

    companion object {
        /** The most values any stream keeps: the width of a slot in [EventRing]. */
        const val MAX_VALUES = 6

        private val all = entries.toTypedArray()

        fun ofOrdinal(ordinal: Int): RecordStream = all[ordinal]

        /** The stream of an Android sensor type, or null for a type that is not recorded. */
        fun of(androidType: Int): RecordStream? = all.firstOrNull { it.androidType == androidType }
    }
}
