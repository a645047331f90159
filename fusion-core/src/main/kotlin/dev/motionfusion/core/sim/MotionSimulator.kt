/*
 * A deterministic, seeded simulator of a moving IMU with known true orientation.
 *
 * Frames: readings in the Android device frame, truth sensor → ENU (v_ENU = q ⊗ v ⊗ q*),
 * quaternions [w, x, y, z] Hamilton. Units: timestamps ns, rad/s, m/s² (specific force: +g on the
 * up axis at rest, as TYPE_ACCELEROMETER), µT.
 *
 * Motion: the device-frame angular velocity is a sum of three sinusoids per axis with random
 * frequencies (0.1–1 Hz) and phases, zero inside rest windows. The truth advances between sampling
 * instants by the exponential of the rate at the interval's midpoint, and the gyroscope sample at
 * the end of the interval reports that rate: integrating the gyroscope over the timestamps
 * reproduces the truth exactly (apart from noise, bias and dropped samples).
 *
 * Violent motions (ViolentMotion: drops, falls, shakes, throws) replace the smooth motion inside their
 * windows; the gyroscope and accelerometer are then clipped at their ranges where these are set.
 *
 * Sensor errors (SimulationSettings): gyroscope = (1 + scale error) · rate + bias + noise; accelerometer =
 * M · specific force + offset + noise; magnetometer = K · field + hard iron + noise. The errors
 * added for calibration draw from a second random sequence, only when set.
 */
package dev.motionfusion.core.sim

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.Matrix3
import java.util.Random
import kotlin.math.PI
import kotlin.math.cos
import kotlin.math.roundToLong
import kotlin.math.sin
import kotlin.math.sqrt

/** One emitted sample: the three sensors at [timestampNs] and the true orientation (sensor → ENU). */
public data class SimulatedSample(
    val timestampNs: Long,
    val gyro: Vector3,
    val acc: Vector3,
    val mag: Vector3,
    val truth: Quaternion,
)

public class MotionSimulator internal constructor(
    public val settings: SimulationSettings,
    /** A constant device-frame angular velocity in place of the random motion (a slew from one pose to another), rad/s. */
    private val constantRate: Vector3?,
) {
    public constructor(settings: SimulationSettings) : this(settings, null)

    private val random = Random(settings.seed)
    private val freq = DoubleArray(9) { 2.0 * PI * (0.1 + 0.9 * random.nextDouble()) }
    private val phase = DoubleArray(9) { 2.0 * PI * random.nextDouble() }

    /** The device-frame angular velocity at time [t] s, rad/s. */
    public fun angularVelocity(t: Double): Vector3 {
        violentAt(t)?.let { return it.rate(t) }
        if (settings.restWindows.any { t in it }) return Vector3.ZERO
        constantRate?.let { return it }
        val a = settings.angularRate / 3.0
        fun axis(k: Int) = a * (sin(freq[3 * k] * t + phase[3 * k]) + sin(freq[3 * k + 1] * t + phase[3 * k + 1]) + sin(freq[3 * k + 2] * t + phase[3 * k + 2]))
        return Vector3(axis(0), axis(1), axis(2))
    }

    /** The world-frame (ENU) linear acceleration at time [t] s, m/s². */
    public fun linearAcceleration(t: Double): Vector3 {
        violentAt(t)?.let { return it.acceleration(t, settings.gravity) }
        val w = settings.linearAccelerationWindow
        if (w == null || t !in w || settings.restWindows.any { t in it }) return Vector3.ZERO
        val a = settings.linearAcceleration
        return Vector3(a * sin(2.0 * PI * 1.3 * t), a * cos(2.0 * PI * 0.7 * t), a * sin(2.0 * PI * 0.9 * t))
    }

    private fun magDisturbanceAt(t: Double): MagneticDisturbance? {
        val v = settings.magDisturbances
        for (i in v.indices) if (t in v[i].window) return v[i]
        return null
    }

    private fun violentAt(t: Double): ViolentMotion? {
        val v = settings.violentMotions
        for (i in v.indices) if (t in v[i].window) return v[i]
        return null
    }

    /** Runs the whole simulation into a list (for short runs; [forEach] streams). */
    public fun run(): List<SimulatedSample> {
        val out = ArrayList<SimulatedSample>((settings.durationS * settings.rateHz).toInt())
        forEach { out.add(it) }
        return out
    }

    /** Runs the whole simulation, handing each sample to [action] in time order (memory independent of the duration). */
    public fun forEach(action: (SimulatedSample) -> Unit) {
        val s = settings
        val period = 1.0 / s.rateHz
        val n = (s.durationS * s.rateHz).toLong()
        val field = Vector3(0.0, s.fieldStrength * cos(s.dip), -s.fieldStrength * sin(s.dip))
        val up = Vector3(0.0, 0.0, s.gravity)
        val errors = Random(s.seed xor ERROR_SEED)
        val gyroDensitySigma = s.gyroNoiseDensity * sqrt(s.rateHz)
        val accDensitySigma = s.accNoiseDensity * sqrt(s.rateHz)
        var accOffset = s.accOffset
        var q = s.initialOrientation
        var bias = s.gyroBias
        var tPrev = 0.0
        for (k in 0L until n) {
            val t = if (k == 0L) 0.0 else k * period + s.timestampJitter * gaussianBounded()
            val dt = t - tPrev
            val rate = if (k == 0L) angularVelocity(0.0) else angularVelocity(0.5 * (t + tPrev))
            if (k > 0L) {
                q = (q * Quaternion.fromRotationVector(rate * dt)).normalized()
                bias += gaussianVector(s.gyroBiasDrift * sqrt(dt))
                if (s.accBiasDrift > 0.0) accOffset += gaussianVector(errors, s.accBiasDrift * sqrt(dt))
            }
            tPrev = t
            val hardIron = if (s.hardIronWindow != null && t in s.hardIronWindow) s.hardIron else Vector3.ZERO
            var gyro = (if (s.gyroScaleError != 0.0) rate * (1.0 + s.gyroScaleError) else rate) + bias + gaussianVector(s.gyroNoise)
            var acc = q.inverseRotate(up + linearAcceleration(t))
            if (s.accMisalignment != Matrix3.IDENTITY) acc = s.accMisalignment * acc
            acc += gaussianVector(s.accNoise)
            var magField = q.inverseRotate(magDisturbanceAt(t)?.field(t, field) ?: field)
            if (s.magSoftIron != Matrix3.IDENTITY) magField = s.magSoftIron * magField
            val mag = magField + hardIron + gaussianVector(s.magNoise)
            if (gyroDensitySigma > 0.0) gyro += gaussianVector(errors, gyroDensitySigma)
            if (accOffset != Vector3.ZERO) acc += accOffset
            if (accDensitySigma > 0.0) acc += gaussianVector(errors, accDensitySigma)
            if (s.gyroRange > 0.0) gyro = clip(gyro, s.gyroRange)
            if (s.accRange > 0.0) acc = clip(acc, s.accRange)
            val dropped = s.dropProbability > 0.0 && random.nextDouble() < s.dropProbability
            if (!dropped || k == 0L) action(SimulatedSample((t * 1e9).roundToLong(), gyro, acc, mag, q))
        }
    }

    private fun clip(v: Vector3, r: Double) = Vector3(v.x.coerceIn(-r, r), v.y.coerceIn(-r, r), v.z.coerceIn(-r, r))

    private fun gaussianVector(sigma: Double): Vector3 = gaussianVector(random, sigma)

    private fun gaussianVector(r: Random, sigma: Double): Vector3 =
        if (sigma == 0.0) Vector3.ZERO else Vector3(sigma * r.nextGaussian(), sigma * r.nextGaussian(), sigma * r.nextGaussian())

    private companion object {
        /** Seed offset of the sensor-error sequence. */
        const val ERROR_SEED = 0x5E4503L
    }

    /** A standard normal number clipped to ±2, so jittered instants stay ordered. */
    private fun gaussianBounded(): Double = random.nextGaussian().coerceIn(-2.0, 2.0)
}
