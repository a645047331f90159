package dev.motionfusion.app.sensor

import android.hardware.Sensor

/** The sensors the app fuses, with their Android type constants and SI units. */
enum class SensorKind(val androidType: Int, val unit: String) {
    ACCELEROMETER(Sensor.TYPE_ACCELEROMETER, "m/s²"),
    GYROSCOPE(Sensor.TYPE_GYROSCOPE, "rad/s"),
    MAGNETOMETER(Sensor.TYPE_MAGNETIC_FIELD, "µT"),
    ;

    companion object {
        /** The kind of an Android sensor type, or null for a type the app does not use. */
        fun of(androidType: Int): SensorKind? = entries.firstOrNull { it.androidType == androidType }
    }
}
