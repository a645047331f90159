package dev.motionfusion.app.fusion

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.core.filter.FilterMode

/** How the orientation is computed, given the sensors the device has and the chosen filter mode. */
enum class FusionMode {
    /** 9D Madgwick: gyroscope, accelerometer and magnetometer. */
    MARG,

    /** 6D Madgwick: gyroscope and accelerometer; heading relative to the start, drifting. */
    IMU,

    /** No gyroscope: accelerometer and magnetometer alone, as SensorManager.getRotationMatrix. */
    ACC_MAG,

    /** No gyroscope and no magnetometer: tilt from the accelerometer, no heading. */
    TILT_ONLY,

    /** No accelerometer: no orientation at all. */
    NONE,
    ;

    /** True when the heading is referenced to magnetic north. */
    val hasMagneticHeading: Boolean get() = this == MARG || this == ACC_MAG
}

/** Why the effective [mode] was chosen (what the screen explains). */
enum class ModeReason { AS_CHOSEN, NO_MAGNETOMETER, NO_GYROSCOPE, NO_GYROSCOPE_NO_MAGNETOMETER, NO_ACCELEROMETER }

data class EffectiveMode(val mode: FusionMode, val reason: ModeReason)

/**
 * The mode that works with the sensors in [available] and comes closest to [requested]:
 * without magnetometer 9D falls back to 6D; without gyroscope the filter is replaced by
 * accelerometer+magnetometer (or tilt only).
 */
fun effectiveMode(available: Set<SensorKind>, requested: FilterMode): EffectiveMode {
    val acc = SensorKind.ACCELEROMETER in available
    val gyro = SensorKind.GYROSCOPE in available
    val mag = SensorKind.MAGNETOMETER in available
    return when {
        !acc -> EffectiveMode(FusionMode.NONE, ModeReason.NO_ACCELEROMETER)
        !gyro && mag -> EffectiveMode(FusionMode.ACC_MAG, ModeReason.NO_GYROSCOPE)
        !gyro -> EffectiveMode(FusionMode.TILT_ONLY, ModeReason.NO_GYROSCOPE_NO_MAGNETOMETER)
        requested == FilterMode.IMU -> EffectiveMode(FusionMode.IMU, ModeReason.AS_CHOSEN)
        !mag -> EffectiveMode(FusionMode.IMU, ModeReason.NO_MAGNETOMETER)
        else -> EffectiveMode(FusionMode.MARG, ModeReason.AS_CHOSEN)
    }
}
