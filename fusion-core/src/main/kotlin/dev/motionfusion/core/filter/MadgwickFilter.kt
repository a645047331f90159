/*
 * The Madgwick orientation filter: S. O. H. Madgwick, "An efficient orientation filter for
 * inertial and inertial/magnetic sensor arrays", University of Bristol, 2010 (the "report").
 * Equation numbers in the comments are the report's.
 *
 * Frames. Inputs in the Android device frame (x right, y up along the screen, z out of the
 * screen). The estimate q̂ = [w, x, y, z] (Hamilton) is the sensor's orientation in the report's
 * North-West-Up earth frame (x magnetic north, y west, z up): v_earth = q̂ ⊗ v_sensor ⊗ q̂*.
 * Readers convert it to FilterSettings.outputFrame (ENU by default, Android's world).
 *
 * Units. Gyroscope rad/s, accelerometer m/s² (specific force, +g on the up axis at rest, as
 * TYPE_ACCELEROMETER), magnetometer µT, timestamps in ns (SensorEvent.timestamp), settings in s.
 *
 * Pairing rule. Android delivers each sensor on its own. The filter holds the latest accelerometer
 * and magnetometer sample and steps on each gyroscope sample, over the time since the previous
 * gyroscope sample, with the held samples if they are no older than maxGap. A non-finite or zero
 * sample replaces the held one by "none" (the next steps run without that correction).
 *
 * Steps. With a usable magnetometer: the MARG update; with only an accelerometer: the IMU update;
 * with neither: gyroscope integration. The report's equations hold exactly with
 * FilterSettings.report(). The additions decide which readings enter (magnetic disturbance,
 * accelerometer rejection, the accelerometer low-passed in a quasi-inertial frame), what bias is removed
 * (rest and motion bias estimates) and the gain of a step (inclination recovery at the start and after
 * a saturated gyroscope reading); with headingGain > 0 the magnetometer corrects heading in a step of its
 * own after the IMU step, instead of entering the report's MARG gradient.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.WorldFrame
import kotlin.math.abs
import kotlin.math.sqrt

/**
 * The Madgwick filter of the report (IMU and MARG gradient-descent updates, normalised gradient,
 * magnetic distortion compensation, gyroscope bias drift compensation ζ) with, as settings: a heading
 * correction apart from inclination, gyroscope bias estimation at rest and in motion, fast heading
 * convergence, magnetic disturbance rejection, accelerometer rejection, the accelerometer low-passed in a
 * quasi-inertial frame, and gyroscope saturation with inclination recovery.
 *
 * Not thread-safe: call from one thread (e.g. the sensor HandlerThread). The update methods
 * allocate nothing.
 */
public class MadgwickFilter(public val settings: FilterSettings = FilterSettings()) {
    private val marg = settings.mode == FilterMode.MARG
    private val beta = settings.beta
    private val zeta = settings.zeta
    private val maxGapNs = (settings.maxGap * 1e9).toLong()
    private val rest = if (settings.restBiasEstimation) RestDetector(settings) else null
    private val restBiasTime = settings.restBiasTime
    private val restMinTime = settings.restMinTime
    private val magDetector = if (settings.magDisturbanceRejection) MagneticDisturbanceDetector(settings) else null
    private val magResume = magDetector != null && settings.magResumeTime > 0.0
    private val accRejection = if (settings.accRejection) AccelerometerRejection(settings) else null
    private val headingGain = settings.headingGain
    private val motionBiasGain = settings.motionBiasGain
    private val biasLimit = settings.motionBiasLimit

    private val headingRecoveryTime = settings.headingRecoveryTime
    private val motionBiasRestTime = settings.motionBiasRestTime
    private val recoveryBeta = settings.inclinationRecoveryBeta
    private val accTrustTime = settings.accTrustTime
    private val accNormTolerance = settings.accNormTolerance
    private val accLowPassTime = settings.accLowPassTime
    private val gyroSaturation = settings.gyroSaturation
    private val cosRecoveryAngle = if (settings.recoveryAngle > 0.0 && recoveryBeta > 0.0) kotlin.math.cos(settings.recoveryAngle) else 2.0
    private val recoveryGyro2 = settings.recoveryGyroThreshold * settings.recoveryGyroThreshold
    private val recoveryStillTime = settings.recoveryStillTime
    private val stillAccThreshold = settings.restAccThreshold

    // How long the phone has been near-still with a trustworthy accelerometer, s (recovery after any large error).
    private var stillTime = 0.0

    // Set at the start and by a saturated gyroscope reading, cleared once inclination has re-converged.
    private var inclinationOff = false

    // The accelerometer low-passed in a frame that turns with the gyroscope only (sensor-frame
    // coordinates, m/s²), the reading the correction steps use when accLowPassTime > 0.
    private var lpx = 0.0
    private var lpy = 0.0
    private var lpz = 0.0
    private var lpFresh = true

    // Time since the low-pass started, s: until it reaches accLowPassTime the value is the mean since then.
    private var lpTime = 0.0

    // β of the current step (β, or inclinationRecoveryBeta while inclination re-converges).
    private var stepBeta = beta

    // How long the accelerometer magnitude has stayed near gravity, s (inclination recovery).
    private var accTrusted = 0.0

    // Time since the rest estimate last acted, s (infinite before it has).
    private var sinceRest = Double.POSITIVE_INFINITY

    // Time since the start or the last new magnetic reference, s (fast heading convergence).
    private var headingClock = 0.0

    // Whether the fast convergence acts: from a heading error above 2° until it is below 0.5°.
    private var headingOff = true
    private val scratch = DoubleArray(4)

    // c, the change from the report's NWU to the output frame: q_out = c ⊗ q̂.
    private val outputChange = WorldFrame.NWU.quaternionTo(settings.outputFrame)

    // Estimate q̂ (NWU), the report's SEq_1..4.
    private var q1 = 1.0
    private var q2 = 0.0
    private var q3 = 0.0
    private var q4 = 0.0

    // Reference direction of flux in the earth frame, b = [0, bx, 0, bz] (eq. 46); the report starts at [0, 1, 0, 0].
    private var bx = 1.0
    private var bz = 0.0

    // Gyroscope bias ω_b (rad/s, device frame).
    private var wbx = 0.0
    private var wby = 0.0
    private var wbz = 0.0

    // Held accelerometer and magnetometer samples.
    private var ax = 0.0
    private var ay = 0.0
    private var az = 0.0
    private var accT = 0L
    private var hasAcc = false
    private var mx = 0.0
    private var my = 0.0
    private var mz = 0.0
    private var magT = 0L
    private var hasMag = false

    private var initialised = false
    private var lastT = 0L
    private var firstAccT = 0L
    private var waitingForMag = false

    private var steps = 0L
    private var skippedBeforeInit = 0L
    private var skippedNonFinite = 0L
    private var skippedOutOfRange = 0L
    private var skippedZero = 0L
    private var skippedTimestamp = 0L
    private var skippedGap = 0L
    private var staleSamples = 0L
    private var accRejections = 0L
    private var magRejections = 0L
    private var saturations = 0L
    private var stillRecoveries = 0L

    /** True once the filter has an orientation. Before that, [orientation] is the identity (of the output frame). */
    public val isInitialised: Boolean get() = initialised

    /** Holds an accelerometer sample (m/s², device frame) for the next gyroscope steps. */
    public fun updateAccelerometer(timestampNs: Long, x: Double, y: Double, z: Double) {
        hasAcc = validVector(x, y, z, SensorRanges.ACCELEROMETER_M_S2)
        ax = x; ay = y; az = z; accT = timestampNs
    }

    /** Holds a magnetometer sample (µT, device frame) for the next gyroscope steps; ignored in IMU mode. */
    public fun updateMagnetometer(timestampNs: Long, x: Double, y: Double, z: Double) {
        if (!marg) return
        hasMag = validVector(x, y, z, SensorRanges.MAGNETOMETER_UT)
        mx = x; my = y; mz = z; magT = timestampNs
    }

    /**
     * One filter step on a gyroscope sample (rad/s, device frame) with the held accelerometer and
     * magnetometer samples (see the pairing rule in the file header). The step length is the time
     * since the previous gyroscope sample; a timestamp that does not advance, or a gap longer than
     * maxGap, is counted and not integrated.
     */
    public fun updateGyroscope(timestampNs: Long, x: Double, y: Double, z: Double) {
        if (!(x.isFinite() && y.isFinite() && z.isFinite())) {
            skippedNonFinite++
            return
        }
        if (abs(x) > SensorRanges.GYROSCOPE_RAD_S || abs(y) > SensorRanges.GYROSCOPE_RAD_S || abs(z) > SensorRanges.GYROSCOPE_RAD_S) {
            skippedOutOfRange++
            return
        }
        val accOk = hasAcc && fresh(timestampNs, accT)
        val magOk = hasMag && fresh(timestampNs, magT)
        if (!initialised) {
            initialise(timestampNs, accOk, magOk)
            return
        }
        if (timestampNs <= lastT) {
            skippedTimestamp++
            lastT = minOf(lastT, timestampNs)
            return
        }
        val gapNs = timestampNs - lastT
        lastT = timestampNs
        if (gapNs > maxGapNs) {
            skippedGap++
            return
        }
        val dt = gapNs * 1e-9
        steps++
        if ((hasAcc && !accOk) || (hasMag && !magOk)) staleSamples++
        if (gyroSaturation != 0.0 && (abs(x) >= gyroSaturation || abs(y) >= gyroSaturation || abs(z) >= gyroSaturation)) saturated()

        if (rest != null && rest.update(dt, x, y, z, accOk, ax, ay, az)) {
            // Mean of the readings since rest began, then a moving average over restBiasTime.
            val k = dt / minOf(restBiasTime, rest.restTime - restMinTime + dt)
            wbx += k * (x - wbx); wby += k * (y - wby); wbz += k * (z - wbz)
            sinceRest = 0.0
        } else if (motionBiasGain != 0.0) {
            sinceRest += dt
        }

        var useAcc = accOk
        if (useAcc && accRejection != null) {
            val n = sqrt(ax * ax + ay * ay + az * az)
            useAcc = accRejection.accept(dt, n, (ax * upX() + ay * upY() + az * upZ()) / n)
            if (!useAcc) accRejections++
        }
        var useMag = magOk
        if (useMag && magDetector != null) {
            val n2 = mx * mx + my * my + mz * mz
            val inv = invSqrt(n2)
            val sinDip = -(mx * upX() + my * upY() + mz * upZ()) * inv
            val sinDipRaw = if (accOk && magDetector.needsReference) -(mx * ax + my * ay + mz * az) * inv * invSqrt(ax * ax + ay * ay + az * az) else sinDip
            val rx = x - wbx
            val ry = y - wby
            val rz = z - wbz
            useMag = magDetector.accept(dt, n2 * inv, sinDip, sinDipRaw, rx * rx + ry * ry + rz * rz)
            if (!useMag) magRejections++
            if (magDetector.newReference && !magResume) headingClock = 0.0
        }
        var cx = ax
        var cy = ay
        var cz = az
        if (cosRecoveryAngle <= 1.0 && !inclinationOff) checkStillError(dt, x - wbx, y - wby, z - wbz, accOk)
        if (accLowPassTime != 0.0) {
            lowPassAcc(dt, x - wbx, y - wby, z - wbz, accOk)
            cx = lpx; cy = lpy; cz = lpz
        }
        if (recoveryBeta != 0.0) stepBeta = if (inclinationOff) recoveringBeta(dt, useAcc, cx, cy, cz) else beta
        when {
            useMag && headingGain == 0.0 -> margStep(dt, x, y, z, useAcc, cx, cy, cz)
            useAcc -> imuStep(dt, x, y, z, cx, cy, cz)
            else -> gyroStep(dt, x, y, z)
        }
        if (useMag && headingGain != 0.0) {
            // Fast convergence (headingRecoveryTime): for that long after the start and after a new
            // magnetic reference, while the heading is off, the gain is at least 1/t, t the time since
            // then (the mean of the errors).
            headingClock += dt
            var k = if (headingClock < headingRecoveryTime && headingOff) maxOf(headingGain, 1.0 / headingClock) else headingGain
            // After a disturbance the gain comes back as a ramp (magResumeTime), the bias estimate with it.
            val f = if (magResume) magDetector!!.gainFactor else 1.0
            k *= f
            val sinDelta = headingStep(dt * k)
            headingOff = abs(sinDelta) > (if (headingOff) SIN_RECOVERY_DONE else SIN_RECOVERY_ERROR)
            if (motionBiasGain != 0.0) motionBias(dt * f, sinDelta)
        }
    }

    /**
     * One step from a table row: gyroscope (rad/s), accelerometer (m/s²) and magnetometer (µT)
     * sampled together at [timestampNs]. Equivalent to the three update calls in the order
     * accelerometer, magnetometer, gyroscope.
     */
    public fun update(
        timestampNs: Long,
        gx: Double, gy: Double, gz: Double,
        ax: Double, ay: Double, az: Double,
        mx: Double, my: Double, mz: Double,
    ) {
        updateAccelerometer(timestampNs, ax, ay, az)
        updateMagnetometer(timestampNs, mx, my, mz)
        updateGyroscope(timestampNs, gx, gy, gz)
    }

    /** One step from a table row without magnetometer (IMU data). */
    public fun update(timestampNs: Long, gx: Double, gy: Double, gz: Double, ax: Double, ay: Double, az: Double) {
        updateAccelerometer(timestampNs, ax, ay, az)
        hasMag = false
        updateGyroscope(timestampNs, gx, gy, gz)
    }

    /** One step from vectors; [mag] null for IMU data. Allocates nothing itself. */
    public fun update(timestampNs: Long, gyro: Vector3, acc: Vector3, mag: Vector3? = null) {
        if (mag == null) {
            update(timestampNs, gyro.x, gyro.y, gyro.z, acc.x, acc.y, acc.z)
        } else {
            update(timestampNs, gyro.x, gyro.y, gyro.z, acc.x, acc.y, acc.z, mag.x, mag.y, mag.z)
        }
    }

    /** The orientation (sensor → earth) in settings.outputFrame; the identity before initialisation. */
    public fun orientation(): Quaternion {
        orientationInto(scratch)
        return Quaternion(scratch[0], scratch[1], scratch[2], scratch[3])
    }

    /** Writes the orientation [w, x, y, z] in settings.outputFrame into out[offset..offset+3]. */
    public fun orientationInto(out: DoubleArray, offset: Int = 0) {
        if (!initialised) {
            out[offset] = 1.0; out[offset + 1] = 0.0; out[offset + 2] = 0.0; out[offset + 3] = 0.0
            return
        }
        // q_out = c ⊗ q̂ (Hamilton product with the fixed frame change c).
        outputChange.timesInto(q1, q2, q3, q4, out, offset)
    }

    /** A copy of the current flags, bias estimate and counters (allocates; not for every sample). */
    public fun diagnostics(): FilterDiagnostics = FilterDiagnostics(
        initialised = initialised,
        gyroBias = Vector3(wbx, wby, wbz),
        atRest = rest?.atRest ?: false,
        magneticDisturbance = magDetector?.disturbed ?: false,
        accelerometerRejected = accRejection?.rejected ?: false,
        gyroscopeSteps = steps,
        skippedBeforeInit = skippedBeforeInit,
        skippedNonFinite = skippedNonFinite,
        skippedOutOfRange = skippedOutOfRange,
        skippedZero = skippedZero,
        skippedTimestamp = skippedTimestamp,
        skippedGap = skippedGap,
        staleSamples = staleSamples,
        accelerometerRejections = accRejections,
        magneticRejections = magRejections,
        gyroscopeSaturations = saturations,
    )

    /** The complete state, for [restore]. */
    public fun snapshot(): FilterSnapshot {
        val d = DoubleArray(DOUBLES + RestDetector.STATE_SIZE + MagneticDisturbanceDetector.STATE_SIZE + AccelerometerRejection.STATE_SIZE)
        val own = doubleArrayOf(q1, q2, q3, q4, bx, bz, wbx, wby, wbz, ax, ay, az, mx, my, mz, headingClock, sinceRest, accTrusted, if (headingOff) 1.0 else 0.0, lpx, lpy, lpz, if (lpFresh) 1.0 else 0.0, if (inclinationOff) 1.0 else 0.0, lpTime, stillTime)
        own.copyInto(d)
        var at = DOUBLES
        at = rest?.writeState(d, at) ?: (at + RestDetector.STATE_SIZE)
        at = magDetector?.writeState(d, at) ?: (at + MagneticDisturbanceDetector.STATE_SIZE)
        accRejection?.writeState(d, at)
        val l = longArrayOf(
            accT, magT, lastT, firstAccT, flags(),
            steps, skippedBeforeInit, skippedNonFinite, skippedZero, skippedTimestamp, skippedGap, staleSamples, accRejections, magRejections, saturations, stillRecoveries, skippedOutOfRange,
        )
        return FilterSnapshot(settings, d, l)
    }

    /**
     * Restores a state taken by [snapshot].
     * @throws IllegalArgumentException if the snapshot was taken under other settings.
     */
    public fun restore(snapshot: FilterSnapshot) {
        require(snapshot.settings == settings) { "snapshot taken under other settings" }
        val d = snapshot.doubles()
        q1 = d[0]; q2 = d[1]; q3 = d[2]; q4 = d[3]; bx = d[4]; bz = d[5]
        wbx = d[6]; wby = d[7]; wbz = d[8]
        ax = d[9]; ay = d[10]; az = d[11]; mx = d[12]; my = d[13]; mz = d[14]
        headingClock = d[15]; sinceRest = d[16]; accTrusted = d[17]; headingOff = d[18] != 0.0
        lpx = d[19]; lpy = d[20]; lpz = d[21]; lpFresh = d[22] != 0.0; inclinationOff = d[23] != 0.0; lpTime = d[24]; stillTime = d[25]
        var at = DOUBLES
        at = rest?.readState(d, at) ?: (at + RestDetector.STATE_SIZE)
        at = magDetector?.readState(d, at) ?: (at + MagneticDisturbanceDetector.STATE_SIZE)
        accRejection?.readState(d, at)
        val l = snapshot.longs()
        accT = l[0]; magT = l[1]; lastT = l[2]; firstAccT = l[3]
        val f = l[4]
        hasAcc = f and 1L != 0L; hasMag = f and 2L != 0L; initialised = f and 4L != 0L; waitingForMag = f and 8L != 0L
        steps = l[5]; skippedBeforeInit = l[6]; skippedNonFinite = l[7]; skippedZero = l[8]; skippedTimestamp = l[9]
        skippedGap = l[10]; staleSamples = l[11]; accRejections = l[12]; magRejections = l[13]; saturations = l[14]; stillRecoveries = l[15]
        skippedOutOfRange = l[16]
    }

    /**
     * Turns the filter round in time, for a pass over the same samples backward (the offline estimate,
     * replay/Offline.kt): the gyroscope readings of such a pass are negated, so the bias estimate and the
     * rest detector's gyroscope low-pass are negated too; the orientation, the field reference, the
     * low-passed accelerometer and the held readings stay. [timestampNs] is the time, on the new pass's
     * clock, of the last step taken: the held readings count as taken then.
     */
    internal fun turnAround(timestampNs: Long) {
        wbx = -wbx; wby = -wby; wbz = -wbz
        rest?.reverse()
        lastT = timestampNs
        accT = timestampNs
        magT = timestampNs
        firstAccT = timestampNs
    }

    /**
     * Takes [q] ([w, x, y, z] in settings.outputFrame, unit) as the estimate, everything else kept, for a pass
     * of the offline estimate that goes on across a gap (replay/Offline.kt): there the other pass's orientation,
     * which has run through the samples beyond the gap, is better than one carried over it. The low-passed
     * accelerometer, held in the frame of the old estimate, starts again from the next reading.
     */
    internal fun takeOrientation(q: DoubleArray) {
        outputChange.conjugate().timesInto(q[0], q[1], q[2], q[3], scratch, 0)
        q1 = scratch[0]; q2 = scratch[1]; q3 = scratch[2]; q4 = scratch[3]
        lpFresh = true
    }

    // Estimated up in the sensor frame, q̂* ⊗ [0, 0, 0, 1] ⊗ q̂ (the terms of eq. 25).
    private fun upX() = 2.0 * (q2 * q4 - q1 * q3)
    private fun upY() = 2.0 * (q1 * q2 + q3 * q4)
    private fun upZ() = 1.0 - 2.0 * (q2 * q2 + q3 * q3)

    private fun flags(): Long =
        (if (hasAcc) 1L else 0L) or (if (hasMag) 2L else 0L) or (if (initialised) 4L else 0L) or (if (waitingForMag) 8L else 0L)

    private fun fresh(t: Long, sampleT: Long): Boolean = t - sampleT <= maxGapNs

    private fun validVector(x: Double, y: Double, z: Double, limit: Double): Boolean {
        if (!(x.isFinite() && y.isFinite() && z.isFinite())) {
            skippedNonFinite++
            return false
        }
        if (abs(x) > limit || abs(y) > limit || abs(z) > limit) {
            skippedOutOfRange++
            return false
        }
        if (x == 0.0 && y == 0.0 && z == 0.0) {
            skippedZero++
            return false
        }
        return true
    }

    /**
     * Starts the filter at the first gyroscope sample that allows it. IDENTITY: at once. FIRST_SAMPLE:
     * needs a fresh accelerometer sample; in MARG mode it also waits for a magnetometer sample, for at
     * most maxGap after the first accelerometer sample, then starts without heading.
     */
    private fun initialise(t: Long, accOk: Boolean, magOk: Boolean) {
        if (settings.initialisation == Initialisation.FIRST_SAMPLE) {
            if (!accOk) {
                skippedBeforeInit++
                return
            }
            if (marg && !magOk) {
                if (!waitingForMag) {
                    waitingForMag = true
                    firstAccT = t
                }
                if (t - firstAccT <= maxGapNs) {
                    skippedBeforeInit++
                    return
                }
            }
            val q = InitialOrientation.nwu(ax, ay, az, magOk, mx, my, mz)
            q1 = q.w; q2 = q.x; q3 = q.y; q4 = q.z
            if (magOk) {
                val n = invSqrt(mx * mx + my * my + mz * mz)
                updateFluxReference(q1, q2, q3, q4, mx * n, my * n, mz * n, 1.0)
            }
        }
        initialised = true
        inclinationOff = true
        lastT = t
    }

    /**
     * The report's MARG update (eqs. 25–26, 29–30, 34, 44, 47–49, 12, 42–43, 45–46). Without
     * [withAcc] (a rejected accelerometer) the accelerometer's rows of f are left out: with b taken
     * from the estimate (eq. 46) the remaining gradient corrects heading only.
     */
    private fun margStep(dt: Double, gx: Double, gy: Double, gz: Double, withAcc: Boolean, ax: Double, ay: Double, az: Double) {
        var f1 = 0.0
        var f2 = 0.0
        var f3 = 0.0
        if (withAcc) {
            val n = invSqrt(ax * ax + ay * ay + az * az)
            // Objective function, accelerometer part (eq. 25).
            f1 = 2.0 * (q2 * q4 - q1 * q3) - ax * n
            f2 = 2.0 * (q1 * q2 + q3 * q4) - ay * n
            f3 = 2.0 * (0.5 - q2 * q2 - q3 * q3) - az * n
        }
        val n = invSqrt(mx * mx + my * my + mz * mz)
        val m1 = mx * n
        val m2 = my * n
        val m3 = mz * n
        val twoBx = 2.0 * bx
        val twoBz = 2.0 * bz
        // Objective function, magnetometer part (eq. 29).
        val f4 = twoBx * (0.5 - q3 * q3 - q4 * q4) + twoBz * (q2 * q4 - q1 * q3) - m1
        val f5 = twoBx * (q2 * q3 - q1 * q4) + twoBz * (q1 * q2 + q3 * q4) - m2
        val f6 = twoBx * (q1 * q3 + q2 * q4) + twoBz * (0.5 - q2 * q2 - q3 * q3) - m3
        // Gradient ∇f = Jᵀ f with the Jacobians of eqs. 26 and 30 (eq. 34).
        val d1 = -2.0 * q3 * f1 + 2.0 * q2 * f2 -
            twoBz * q3 * f4 + (-twoBx * q4 + twoBz * q2) * f5 + twoBx * q3 * f6
        val d2 = 2.0 * q4 * f1 + 2.0 * q1 * f2 - 4.0 * q2 * f3 +
            twoBz * q4 * f4 + (twoBx * q3 + twoBz * q1) * f5 + (twoBx * q4 - 2.0 * twoBz * q2) * f6
        val d3 = -2.0 * q1 * f1 + 2.0 * q4 * f2 - 4.0 * q3 * f3 +
            (-2.0 * twoBx * q3 - twoBz * q1) * f4 + (twoBx * q2 + twoBz * q4) * f5 + (twoBx * q1 - 2.0 * twoBz * q3) * f6
        val d4 = 2.0 * q2 * f1 + 2.0 * q3 * f2 +
            (-2.0 * twoBx * q4 + twoBz * q2) * f4 + (-twoBx * q1 + twoBz * q3) * f5 + twoBx * q2 * f6
        correct(dt, gx, gy, gz, d1, d2, d3, d4, zeta, true, m1, m2, m3)
    }

    /** The report's IMU update (eqs. 25–26, 34, 44, 12, 42–43); the report has no ζ here. */
    private fun imuStep(dt: Double, gx: Double, gy: Double, gz: Double, ax: Double, ay: Double, az: Double) {
        val n = invSqrt(ax * ax + ay * ay + az * az)
        val f1 = 2.0 * (q2 * q4 - q1 * q3) - ax * n
        val f2 = 2.0 * (q1 * q2 + q3 * q4) - ay * n
        val f3 = 2.0 * (0.5 - q2 * q2 - q3 * q3) - az * n
        correct(
            dt, gx, gy, gz,
            -2.0 * q3 * f1 + 2.0 * q2 * f2,
            2.0 * q4 * f1 + 2.0 * q1 * f2 - 4.0 * q2 * f3,
            -2.0 * q1 * f1 + 2.0 * q4 * f2 - 4.0 * q3 * f3,
            2.0 * q2 * f1 + 2.0 * q3 * f2,
            0.0, false, 0.0, 0.0, 0.0,
        )
    }

    /**
     * Heading correction apart from inclination (beyond the report; headingGain > 0): the measured
     * field in the earth frame, h = q̂ ⊗ m ⊗ q̂*, should point north (+x of NWU). The estimate is
     * turned about the earth's vertical towards that, by the fraction [k] of the heading error δ
     * (sin δ for |δ| < 90°, a quarter turn beyond), so inclination is left as the accelerometer made it.
     */
    private fun headingStep(k: Double): Double {
        val hx = earthX(q1, q2, q3, q4, mx, my, mz)
        val hy = earthY(q1, q2, q3, q4, mx, my, mz)
        val hn2 = hx * hx + hy * hy
        if (!(hn2 > 0.0)) return 0.0
        val sinDelta = if (hx > 0.0) hy * invSqrt(hn2) else if (hy >= 0.0) 1.0 else -1.0
        // q̂ ← [cos(a/2), 0, 0, sin(a/2)] ⊗ q̂ with a = −k·sin δ (small: cos ≈ 1, then normalised).
        val s = -0.5 * minOf(k, 1.0) * sinDelta
        val n1 = q1 - s * q4
        val n2 = q2 - s * q3
        val n3 = q3 + s * q2
        val n4 = q4 + s * q1
        val inv = invSqrt(n1 * n1 + n2 * n2 + n3 * n3 + n4 * n4)
        q1 = n1 * inv; q2 = n2 * inv; q3 = n3 * inv; q4 = n4 * inv
        return sinDelta
    }

    /**
     * A gyroscope reading clipped at the sensor's range (gyroSaturation): the rotation it integrates
     * is short of the true one by an unknown amount, so the estimate can be off in any direction. The
     * low-passed accelerometer (whose frame turned with that rotation) starts again from the next
     * reading, inclination recovery is armed (inclinationRecoveryBeta) and fast heading convergence
     * starts again (headingRecoveryTime).
     */
    private fun saturated() {
        saturations++
        lpFresh = true
        inclinationOff = true
        accTrusted = 0.0
        headingClock = 0.0
        headingOff = true
    }

    /**
     * Recovery after any large error (recoveryAngle > 0): while the phone is near-still (bias-corrected
     * rate [wx], [wy], [wz] below recoveryGyroThreshold) and the accelerometer's magnitude is within
     * restAccThreshold of standard gravity, the reading is gravity within a fraction of a degree. Once
     * that has held for recoveryStillTime, an estimated up further than recoveryAngle from the reading
     * means the estimate was put off (an impact, a shake, a fall: motions that need not reach the
     * gyroscope's range): the low-passed accelerometer, which went through the same motion, starts
     * again from the still readings and the inclination recovery acts at once. Costs a few
     * multiplications and one square root per step; nothing while a recovery runs.
     */
    private fun checkStillError(dt: Double, wx: Double, wy: Double, wz: Double, accOk: Boolean) {
        if (!accOk || wx * wx + wy * wy + wz * wz >= recoveryGyro2) {
            stillTime = 0.0
            return
        }
        val n = sqrt(ax * ax + ay * ay + az * az)
        if (abs(n - STANDARD_GRAVITY) >= stillAccThreshold) {
            stillTime = 0.0
            return
        }
        stillTime += dt
        if (stillTime >= recoveryStillTime && ax * upX() + ay * upY() + az * upZ() < cosRecoveryAngle * n) {
            stillRecoveries++
            inclinationOff = true
            lpFresh = true
            accTrusted = accTrustTime
            stillTime = 0.0
        }
    }

    /**
     * Inclination recovery after violent motion (inclinationRecoveryBeta > 0, armed at the start and by a
     * saturated gyroscope reading): the accelerometer is trusted again once its magnitude has stayed
     * within accNormTolerance of standard gravity for accTrustTime; then the step gain is
     * inclinationRecoveryBeta until the reading the step uses (c, low-passed with accLowPassTime) is
     * within 1° of the estimated up, for at most 10 s (linear acceleration may keep it further); then β
     * again and the recovery is over.
     */
    private fun recoveringBeta(dt: Double, withAcc: Boolean, cx: Double, cy: Double, cz: Double): Double {
        if (!withAcc) {
            accTrusted = 0.0
            return beta
        }
        val n = sqrt(ax * ax + ay * ay + az * az)
        if (abs(n - STANDARD_GRAVITY) > accNormTolerance) {
            accTrusted = 0.0
            return beta
        }
        accTrusted += dt
        if (accTrusted < accTrustTime) return beta
        if (accTrusted < accTrustTime + MAX_RECOVERY_TIME && cx * upX() + cy * upY() + cz * upZ() < COS_RECOVERY_DONE * sqrt(cx * cx + cy * cy + cz * cz)) return recoveryBeta
        inclinationOff = false
        return beta
    }

    /**
     * Gyroscope bias estimation during motion (beyond the report; motionBiasGain > 0 with
     * headingGain > 0): the heading error the heading step removes, as a rotation rate about the
     * estimated up in the sensor frame, e = −sin δ·v̂, is integrated into the bias, as the integral
     * term of a PI observer: ω_b −= k·e·Δt, each axis limited to ±motionBiasLimit. (The same with
     * the accelerometer's error, â × v̂, was measured and hurts: linear acceleration leaks into it.)
     */
    private fun motionBias(dt: Double, sinDelta: Double) {
        // After a rest estimate, the gain ramps up from 0 over motionBiasRestTime: the rest estimate
        // is the better one until the bias may have drifted away from it.
        val ramp = if (sinceRest < motionBiasRestTime) sinceRest / motionBiasRestTime else 1.0
        val k = motionBiasGain * ramp * dt * sinDelta
        wbx = (wbx + k * upX()).coerceIn(-biasLimit, biasLimit)
        wby = (wby + k * upY()).coerceIn(-biasLimit, biasLimit)
        wbz = (wbz + k * upZ()).coerceIn(-biasLimit, biasLimit)
    }

    /**
     * The accelerometer low-passed in a quasi-inertial frame (beyond the report; accLowPassTime > 0):
     * the held value, a vector fixed in a frame that turns with the bias-corrected gyroscope
     * (w_x, w_y, w_z), is first turned with it, v ← R(−ωΔt) v (Rodrigues' formula to fourth order in
     * |ω|Δt), then moved towards the reading with the time constant accLowPassTime. Gravity is fixed in
     * that frame and passes unchanged; linear acceleration, whose integral is a bounded velocity,
     * averages out. A reading the accelerometer rejection leaves out still enters the low-pass (the steps
     * then do without it). Without a fresh reading the low-pass stops; the next reading starts it again, and
     * until accLowPassTime has passed since then the value is the mean of the readings since (turned
     * alike), so a start in motion is not held for long.
     */
    private fun lowPassAcc(dt: Double, wx: Double, wy: Double, wz: Double, withAcc: Boolean) {
        if (!withAcc) {
            lpFresh = true
            return
        }
        if (lpFresh) {
            lpx = ax; lpy = ay; lpz = az
            lpFresh = false
            lpTime = 0.0
            return
        }
        val rx = wx * dt
        val ry = wy * dt
        val rz = wz * dt
        val t2 = rx * rx + ry * ry + rz * rz
        val s1 = 1.0 - t2 * (1.0 / 6.0) // sin θ / θ
        val s2 = 0.5 - t2 * (1.0 / 24.0) // (1 − cos θ) / θ²
        // r × v and r × (r × v), turned by −θ: v' = v − s1 (r × v) + s2 r × (r × v).
        val cx = ry * lpz - rz * lpy
        val cy = rz * lpx - rx * lpz
        val cz = rx * lpy - ry * lpx
        val vx = lpx - s1 * cx + s2 * (ry * cz - rz * cy)
        val vy = lpy - s1 * cy + s2 * (rz * cx - rx * cz)
        val vz = lpz - s1 * cz + s2 * (rx * cy - ry * cx)
        val k = dt / (minOf(lpTime, accLowPassTime) + dt)
        lpTime += dt
        lpx = vx + k * (ax - vx)
        lpy = vy + k * (ay - vy)
        lpz = vz + k * (az - vz)
    }

    /** Gyroscope integration only (no usable accelerometer): eq. 12 with the bias removed. */
    private fun gyroStep(dt: Double, gx: Double, gy: Double, gz: Double) {
        correct(dt, gx, gy, gz, 0.0, 0.0, 0.0, 0.0, 0.0, false, 0.0, 0.0, 0.0)
    }

    /**
     * Normalises the gradient (d1..d4) (eq. 44), updates the bias with gain [z] (eqs. 47–48),
     * removes it (eq. 49) and integrates (eqs. 12, 42–43); with [flux], updates b from the
     * normalised magnetometer reading (m1, m2, m3) (eqs. 45–46). A zero gradient (exact agreement)
     * contributes no correction. A step whose result is not finite is dropped.
     */
    private fun correct(
        dt: Double, gx: Double, gy: Double, gz: Double,
        d1: Double, d2: Double, d3: Double, d4: Double, z: Double,
        flux: Boolean, m1: Double, m2: Double, m3: Double,
    ) {
        // The gyroscope term with the previous bias does not depend on the gradient: computed first,
        // it overlaps with the gradient's normalisation.
        val h = 0.5 * dt
        val wx = gx - wbx // (eq. 49)
        val wy = gy - wby
        val wz = gz - wbz
        val p1 = q1 + h * (-q2 * wx - q3 * wy - q4 * wz)
        val p2 = q2 + h * (q1 * wx + q3 * wz - q4 * wy)
        val p3 = q3 + h * (q1 * wy - q2 * wz + q4 * wx)
        val p4 = q4 + h * (q1 * wz + q2 * wy - q3 * wx)
        val dn2 = d1 * d1 + d2 * d2 + d3 * d3 + d4 * d4
        val s = if (dn2 > 0.0) invSqrt(dn2) else 0.0
        val e1 = d1 * s
        val e2 = d2 * s
        val e3 = d3 * s
        val e4 = d4 * s
        // q̂ += (½ q̂ ⊗ [0, ω − ω_b] − β q̇_ε) Δt (eqs. 12, 42–43).
        var c1 = stepBeta * dt
        var c2 = 0.0
        if (z != 0.0) {
            // ω_ε = 2 q̂* ⊗ q̇_ε (eq. 47); ω_b += ζ ω_ε Δt (eq. 48). The bias change Δω_b = ζΔt ω_ε enters
            // the rate as ½ q̂ ⊗ [0, −Δω_b] = −ζΔt (q̇_ε − (q̂·q̇_ε) q̂), because q̂ ⊗ (q̂* ⊗ q̇_ε) = q̇_ε.
            val k = z * dt
            wbx += 2.0 * k * (q1 * e2 - q2 * e1 - q3 * e4 + q4 * e3)
            wby += 2.0 * k * (q1 * e3 + q2 * e4 - q3 * e1 - q4 * e2)
            wbz += 2.0 * k * (q1 * e4 - q2 * e3 + q3 * e2 - q4 * e1)
            val kdt = k * dt
            c1 += kdt
            c2 = kdt * (q1 * e1 + q2 * e2 + q3 * e3 + q4 * e4)
        }
        val n1 = p1 - c1 * e1 + c2 * q1
        val n2 = p2 - c1 * e2 + c2 * q2
        val n3 = p3 - c1 * e3 + c2 * q3
        val n4 = p4 - c1 * e4 + c2 * q4
        val n = n1 * n1 + n2 * n2 + n3 * n3 + n4 * n4
        val inv = invSqrt(n)
        if (!(inv > 0.0 && inv.isFinite())) {
            skippedNonFinite++
            return
        }
        q1 = n1 * inv; q2 = n2 * inv; q3 = n3 * inv; q4 = n4 * inv
        // b from the new estimate: computed from the unnormalised n, scaled by 1/|n|², so that it
        // does not wait for the normalisation.
        if (flux) updateFluxReference(n1, n2, n3, n4, m1, m2, m3, 1.0 / n)
    }

    /**
     * Magnetic distortion compensation (eqs. 45–46): h = q̂ ⊗ [0, m] ⊗ q̂*, b = [0, √(hx² + hy²), 0, hz],
     * with q̂ = p/|p| given as p = (p1..p4) and [s] = 1/|p|² (h is quadratic in q̂).
     */
    private fun updateFluxReference(p1: Double, p2: Double, p3: Double, p4: Double, m1: Double, m2: Double, m3: Double, s: Double) {
        val hx = earthX(p1, p2, p3, p4, m1, m2, m3)
        val hy = earthY(p1, p2, p3, p4, m1, m2, m3)
        val hz = m3 * (p1 * p1 - p2 * p2 - p3 * p3 + p4 * p4) + 2.0 * (m1 * (p2 * p4 - p1 * p3) + m2 * (p3 * p4 + p1 * p2))
        bx = sqrt(hx * hx + hy * hy) * s
        bz = hz * s
    }

    // x and y of p ⊗ [0, m] ⊗ p* (|p|² times the rotated vector): the horizontal part of m in the earth frame.
    private fun earthX(p1: Double, p2: Double, p3: Double, p4: Double, m1: Double, m2: Double, m3: Double) =
        m1 * (p1 * p1 + p2 * p2 - p3 * p3 - p4 * p4) + 2.0 * (m2 * (p2 * p3 - p1 * p4) + m3 * (p2 * p4 + p1 * p3))

    private fun earthY(p1: Double, p2: Double, p3: Double, p4: Double, m1: Double, m2: Double, m3: Double) =
        m2 * (p1 * p1 - p2 * p2 + p3 * p3 - p4 * p4) + 2.0 * (m1 * (p2 * p3 + p1 * p4) + m3 * (p3 * p4 - p1 * p2))

    private companion object {
        const val DOUBLES = 26

        /** sin of the heading errors at which the fast convergence starts (2°) and ends (0.5°). */
        val SIN_RECOVERY_ERROR = kotlin.math.sin(2.0 * Math.PI / 180.0)
        val SIN_RECOVERY_DONE = kotlin.math.sin(0.5 * Math.PI / 180.0)

        /** Inclination recovery ends within 1° of the accelerometer, or after 10 s of acting. */
        val COS_RECOVERY_DONE = kotlin.math.cos(1.0 * Math.PI / 180.0)
        const val MAX_RECOVERY_TIME = 10.0

        /** 1/√x as √x · (1/x): the square root and the division run in parallel (shorter latency than 1/√x). */
        fun invSqrt(x: Double): Double = sqrt(x) * (1.0 / x)
    }
}
