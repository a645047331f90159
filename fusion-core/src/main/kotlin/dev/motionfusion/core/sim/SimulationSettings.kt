/*
 * Settings of the motion simulator. Device frame: Android's (x right, y up along the screen, z
 * out of the screen). World frame: East-North-Up. Units: SI (s, rad, rad/s, m/s², µT).
 */
package dev.motionfusion.core.sim

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.Matrix3
import kotlin.math.PI

/** A time window [startS, endS) in seconds from the start of a simulation. */
public data class TimeWindow(val startS: Double, val endS: Double) {
    init {
        require(startS.isFinite() && endS.isFinite() && endS >= startS) { "bad window [$startS, $endS)" }
    }

    public operator fun contains(t: Double): Boolean = t >= startS && t < endS
}

/**
 * What to simulate. Every random quantity comes from [seed]: equal settings give equal streams.
 *
 * @property rateHz nominal sampling rate of all three sensors, Hz.
 * @property durationS length, s.
 * @property initialOrientation true orientation at t = 0, sensor → ENU.
 * @property angularRate amplitude of the smooth random rotation about each device axis, rad/s.
 * @property restWindows windows in which the device does not rotate or accelerate.
 * @property gyroNoise standard deviation of white gyroscope noise, rad/s.
 * @property accNoise standard deviation of white accelerometer noise, m/s².
 * @property magNoise standard deviation of white magnetometer noise, µT.
 * @property gyroBias gyroscope bias at t = 0, rad/s, device frame.
 * @property gyroBiasDrift random-walk intensity of the bias, rad/s per √s.
 * @property fieldStrength earth field magnitude, µT.
 * @property dip dip angle of the field below the horizontal, rad (positive: northern hemisphere).
 * @property gravity magnitude of gravity, m/s².
 * @property hardIron offset added to the magnetometer (device frame, µT) during [hardIronWindow].
 * @property hardIronWindow when [hardIron] applies; null: never.
 * @property linearAcceleration amplitude of a smooth world-frame acceleration, m/s², during [linearAccelerationWindow].
 * @property linearAccelerationWindow when it applies; null: never.
 * @property timestampJitter standard deviation of the true sampling instants around the nominal grid, s
 *   (the timestamps report the true instants, as SensorEvent.timestamp does).
 * @property dropProbability probability that a sample is lost (not emitted).
 *
 * Sensor errors for calibration (docs/CALIBRATION.md); their defaults add nothing, and they draw
 * from a random sequence of their own, so settings without them give the same streams as before:
 * @property magSoftIron soft iron K: magnetometer = K · field + hard iron + noise (symmetric, positive definite).
 * @property accMisalignment scale and misalignment M: accelerometer = M · specific force + [accOffset] + noise.
 * @property accOffset accelerometer offset at t = 0, m/s².
 * @property accBiasDrift random-walk intensity of the accelerometer offset, m/s² per √s (m/s³/√Hz).
 * @property gyroNoiseDensity white gyroscope noise density, rad/s/√Hz (σ per sample = density · √[rateHz]), added to [gyroNoise].
 * @property accNoiseDensity white accelerometer noise density, m/s²/√Hz, added to [accNoise].
 *
 * Violent motion and the limits of real sensors (defaults: none, so the streams stay as before):
 * @property violentMotions drops, falls, shakes and throws ([ViolentMotion]); inside their windows they
 *   replace the smooth motion and the rest windows.
 * @property accRange each accelerometer axis is clipped at ±this, m/s² (phones: 2, 4, 8 or 16 g); 0: no clipping.
 * @property gyroRange each gyroscope axis is clipped at ±this, rad/s (±2000°/s: 34.9 rad/s); 0: no clipping.
 * @property gyroScaleError relative scale error of the gyroscope (0.01: it reads 1 % more than the rate).
 * @property magDisturbances ferrous objects passing and halls with their own field ([MagneticDisturbance]);
 *   inside their windows the magnetometer senses their field instead of the earth's (default: none).
 */
public data class SimulationSettings(
    val seed: Long = 1L,
    val rateHz: Double = 200.0,
    val durationS: Double = 60.0,
    val initialOrientation: Quaternion = Quaternion.fromAxisAngle(Vector3(1.0, 2.0, 3.0), 1.0),
    val angularRate: Double = 1.0,
    val restWindows: List<TimeWindow> = emptyList(),
    val gyroNoise: Double = 0.002,
    val accNoise: Double = 0.03,
    val magNoise: Double = 0.3,
    val gyroBias: Vector3 = Vector3.ZERO,
    val gyroBiasDrift: Double = 0.0,
    val fieldStrength: Double = 48.0,
    val dip: Double = 60.0 * PI / 180.0,
    val gravity: Double = 9.80665,
    val hardIron: Vector3 = Vector3.ZERO,
    val hardIronWindow: TimeWindow? = null,
    val linearAcceleration: Double = 0.0,
    val linearAccelerationWindow: TimeWindow? = null,
    val timestampJitter: Double = 0.0,
    val dropProbability: Double = 0.0,
    val magSoftIron: Matrix3 = Matrix3.IDENTITY,
    val accMisalignment: Matrix3 = Matrix3.IDENTITY,
    val accOffset: Vector3 = Vector3.ZERO,
    val accBiasDrift: Double = 0.0,
    val gyroNoiseDensity: Double = 0.0,
    val accNoiseDensity: Double = 0.0,
    val violentMotions: List<ViolentMotion> = emptyList(),
    val accRange: Double = 0.0,
    val gyroRange: Double = 0.0,
    val gyroScaleError: Double = 0.0,
    val magDisturbances: List<MagneticDisturbance> = emptyList(),
) {
    init {
        require(rateHz.isFinite() && rateHz > 0.0) { "rateHz must be > 0: $rateHz" }
        require(durationS.isFinite() && durationS > 0.0) { "durationS must be > 0: $durationS" }
        require(initialOrientation.isFinite() && kotlin.math.abs(initialOrientation.norm() - 1.0) < 1e-9) { "initialOrientation must be a unit quaternion" }
        for ((name, v) in listOf(
            "angularRate" to angularRate, "gyroNoise" to gyroNoise, "accNoise" to accNoise, "magNoise" to magNoise,
            "gyroBiasDrift" to gyroBiasDrift, "fieldStrength" to fieldStrength, "gravity" to gravity,
            "linearAcceleration" to linearAcceleration, "timestampJitter" to timestampJitter,
            "accBiasDrift" to accBiasDrift, "gyroNoiseDensity" to gyroNoiseDensity, "accNoiseDensity" to accNoiseDensity,
            "accRange" to accRange, "gyroRange" to gyroRange,
        )) require(v.isFinite() && v >= 0.0) { "$name must be finite and ≥ 0: $v" }
        require(dip.isFinite() && kotlin.math.abs(dip) <= PI / 2) { "dip must be in [−π/2, π/2]: $dip" }
        require(gyroBias.isFinite() && hardIron.isFinite() && accOffset.isFinite()) { "vectors must be finite" }
        require(magSoftIron.isFinite() && magSoftIron.determinant() > 0.0) { "magSoftIron must be finite with a positive determinant" }
        require(accMisalignment.isFinite() && accMisalignment.determinant() > 0.0) { "accMisalignment must be finite with a positive determinant" }
        require(timestampJitter < 0.25 / rateHz) { "timestampJitter must be below a quarter sample period" }
        require(gyroScaleError.isFinite() && kotlin.math.abs(gyroScaleError) < 0.5) { "gyroScaleError must be in (−0.5, 0.5): $gyroScaleError" }
        require(dropProbability in 0.0..0.5) { "dropProbability must be in [0, 0.5]: $dropProbability" }
    }
}
