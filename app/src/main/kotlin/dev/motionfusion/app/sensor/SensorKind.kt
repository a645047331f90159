package dev.motionfusion.app.sensor

import android.hardware.Sensor

/**
 * The sensors the app listens to, with their Android type constants and units.
 * [ACCELEROMETER], [GYROSCOPE] and [MAGNETOMETER] feed the filter (device frame, SI units);
 * [ROTATION_VECTOR] and [GAME_ROTATION_VECTOR] are the phone's own fusion, kept as references:
 * unit quaternion of the rotation device → world (East-North-Up; for the game vector the
 * heading is arbitrary), values[0..2] = axis·sin(θ/2) and values[3] = cos(θ/2).
 */
enum class SensorKind(val androidType: Int, val unit: String) {
    ACCELEROMETER(Sensor.TYPE_ACCELEROMETER, "m/s²"),
    GYROSCOPE(Sensor.TYPE_GYROSCOPE, "rad/s"),
    MAGNETOMETER(Sensor.TYPE_MAGNETIC_FIELD, "µT"),
    ROTATION_VECTOR(Sensor.TYPE_ROTATION_VECTOR, "1"),
    GAME_ROTATION_VECTOR(Sensor.TYPE_GAME_ROTATION_VECTOR, "1"),
    ;

    /** True for the rotation vectors, whose samples carry a fourth value [SensorSample.w]. */
    val isRotationVector: Boolean get() = this == ROTATION_VECTOR || this == GAME_ROTATION_VECTOR

    companion object {
        /** The kind of an Android sensor type, or null for a type the app does not use. */
        fun of(androidType: Int): SensorKind? = entries.firstOrNull { it.androidType == androidType }
    }
}
