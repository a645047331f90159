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
 * FilterSettings.report().
 *
 * Composition. Each mechanism beyond the report is a unit of its own (internal class, its settings
 * taken from FilterSettings, its own state, reset(), and its part of the snapshot, in this order):
 *   GyroBiasEstimate      the bias ω_b: rest detection (RestDetector) and the rest and motion estimates
 *   MagneticDisturbanceDetector   whether the magnetometer enters, and the heading gain's resume ramp
 *   AccelerometerRejection        whether the accelerometer enters
 *   AccelerometerLowPass  the accelerometer low-passed in a quasi-inertial frame, what the steps use
 *   InclinationRecovery   the step gain β: armed at the start, by a saturated gyroscope reading and
 *                         by a still error; trusts the accelerometer again, then acts until re-converged
 *   HeadingCorrection     the heading step's gain (headingGain > 0) with its fast convergence
 * The filter itself holds q̂, the flux reference b, the held readings and the counters. One gyroscope
 * step (updateGyroscope) reads as: saturation → bias (rest) → which readings enter → still error →
 * low-pass → gain → gradient step (MARG, IMU or gyroscope only) → heading step → bias (motion).
 * snapshot()/restore() hold all of it (the filter's own doubles, then each unit's), so a run stopped
 * and resumed continues bit for bit (StopResumeTest).
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
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
    private val gyroSaturation = settings.gyroSaturation

    // The mechanisms beyond the report, each with its own settings and state (see the file header).
    private val bias = GyroBiasEstimate(settings)
    private val magDetector = if (settings.magDisturbanceRejection) MagneticDisturbanceDetector(settings) else null
    private val magResume = magDetector != null && settings.magResumeTime > 0.0
    private val magScaled = magDetector != null && (settings.magResumeTime > 0.0 || settings.magRejectionFactor > 0.0)
    private val accRejection = if (settings.accRejection) AccelerometerRejection(settings) else null
    private val lowPass = AccelerometerLowPass(settings)
    private val recovery = InclinationRecovery(settings)
    private val heading = HeadingCorrection(settings)

    // β of the current step (β, or inclinationRecoveryBeta while inclination re-converges).
    private var stepBeta = beta
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
    private var magTooStrong = false

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
        // A field stronger than the earth's is no heading (a magnet, or a raw reading with its hard-iron offset).
        magTooStrong = hasMag && !SensorRanges.isEarthField(x, y, z)
        if (magTooStrong) hasMag = false
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
        if (magTooStrong && fresh(timestampNs, magT)) magRejections++
        if (gyroSaturation != 0.0 && (abs(x) >= gyroSaturation || abs(y) >= gyroSaturation || abs(z) >= gyroSaturation)) saturated()
        // The estimated up in the sensor frame before the step, q̂* ⊗ [0, 0, 0, 1] ⊗ q̂ (the terms of eq. 25).
        val ux = upX()
        val uy = upY()
        val uz = upZ()

        // Bias: the rest estimate (the motion estimate follows the heading step).
        bias.update(dt, x, y, z, accOk, ax, ay, az)
        val wx = x - bias.x
        val wy = y - bias.y
        val wz = z - bias.z

        // Which readings enter.
        val useAcc = accOk && accelerometerEnters(dt, ux, uy, uz)
        val useMag = magOk && magnetometerEnters(dt, accOk, ux, uy, uz, wx * wx + wy * wy + wz * wz)
        if (recovery.stillError(dt, wx, wy, wz, accOk, ax, ay, az, ux, uy, uz)) {
            stillRecoveries++
            lowPass.restart()
        }
        var cx = ax
        var cy = ay
        var cz = az
        if (lowPass.enabled) {
            lowPass.update(dt, wx, wy, wz, accOk, ax, ay, az)
            cx = lowPass.x; cy = lowPass.y; cz = lowPass.z
        }

        // Gain, then the gradient step (the heading step after it).
        stepBeta = recovery.beta(dt, useAcc, ax, ay, az, cx, cy, cz, ux, uy, uz)
        when {
            useMag && !heading.enabled -> margStep(dt, x, y, z, useAcc, cx, cy, cz)
            useAcc -> imuStep(dt, x, y, z, cx, cy, cz)
            else -> gyroStep(dt, x, y, z)
        }
        if (useMag && heading.enabled) {
            // After a disturbance the gain comes back as a ramp (magResumeTime), the bias estimate with it;
            // a disturbed field used after the hold's budget is spent enters at a reduced gain (magRejectionFactor).
            val f = if (magScaled) magDetector!!.gainFactor else 1.0
            val sinDelta = headingStep(dt * heading.gain(dt, f))
            heading.observe(sinDelta)
            if (bias.inMotion) bias.motion(dt * f, sinDelta, upX(), upY(), upZ())
        }
    }

    /** Accelerometer rejection (when on): whether the held reading enters this step; ([ux], [uy], [uz]) the estimated up. */
    private fun accelerometerEnters(dt: Double, ux: Double, uy: Double, uz: Double): Boolean {
        if (accRejection == null) return true
        val n = sqrt(ax * ax + ay * ay + az * az)
        val use = accRejection.accept(dt, n, (ax * ux + ay * uy + az * uz) / n)
        if (!use) accRejections++
        return use
    }

    /**
     * Magnetic disturbance rejection (when on): whether the held reading enters this step, its dip measured
     * against the estimated up ([ux], [uy], [uz]), or the accelerometer's when [accOk] and a new reference
     * is taken; [rate2] the squared bias-corrected rate. A new reference starts the heading's fast convergence
     * again (without the resume ramp).
     */
    private fun magnetometerEnters(dt: Double, accOk: Boolean, ux: Double, uy: Double, uz: Double, rate2: Double): Boolean {
        val detector = magDetector ?: return true
        val n2 = mx * mx + my * my + mz * mz
        val inv = invSqrt(n2)
        val sinDip = -(mx * ux + my * uy + mz * uz) * inv
        val sinDipRaw = if (accOk && detector.needsReference) -(mx * ax + my * ay + mz * az) * inv * invSqrt(ax * ax + ay * ay + az * az) else sinDip
        val use = detector.accept(dt, n2 * inv, sinDip, sinDipRaw, rate2)
        if (!use) magRejections++
        if (detector.newReference && !magResume) heading.newReference()
        return use
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
        gyroBias = Vector3(bias.x, bias.y, bias.z),
        atRest = bias.atRest,
        magneticDisturbance = (magDetector?.disturbed ?: false) || magTooStrong,
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
        val d = DoubleArray(STATE_DOUBLES)
        val own = doubleArrayOf(q1, q2, q3, q4, bx, bz, ax, ay, az, mx, my, mz)
        own.copyInto(d)
        var at = DOUBLES
        at = bias.writeState(d, at)
        at = magDetector?.writeState(d, at) ?: (at + MagneticDisturbanceDetector.STATE_SIZE)
        at = accRejection?.writeState(d, at) ?: (at + AccelerometerRejection.STATE_SIZE)
        at = lowPass.writeState(d, at)
        at = recovery.writeState(d, at)
        heading.writeState(d, at)
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
        ax = d[6]; ay = d[7]; az = d[8]; mx = d[9]; my = d[10]; mz = d[11]
        var at = DOUBLES
        at = bias.readState(d, at)
        at = magDetector?.readState(d, at) ?: (at + MagneticDisturbanceDetector.STATE_SIZE)
        at = accRejection?.readState(d, at) ?: (at + AccelerometerRejection.STATE_SIZE)
        at = lowPass.readState(d, at)
        at = recovery.readState(d, at)
        heading.readState(d, at)
        val l = snapshot.longs()
        accT = l[0]; magT = l[1]; lastT = l[2]; firstAccT = l[3]
        val f = l[4]
        hasAcc = f and 1L != 0L; hasMag = f and 2L != 0L; initialised = f and 4L != 0L; waitingForMag = f and 8L != 0L; magTooStrong = f and 16L != 0L
        steps = l[5]; skippedBeforeInit = l[6]; skippedNonFinite = l[7]; skippedZero = l[8]; skippedTimestamp = l[9]
        skippedGap = l[10]; staleSamples = l[11]; accRejections = l[12]; magRejections = l[13]; saturations = l[14]; stillRecoveries = l[15]
        skippedOutOfRange = l[16]
    }

    /** Back to the state of a new filter with the same settings (every unit's state and the counters included). */
    internal fun reset() {
        bias.reset()
        magDetector?.reset()
        accRejection?.reset()
        lowPass.reset()
        recovery.reset()
        heading.reset()
        stepBeta = beta
        q1 = 1.0; q2 = 0.0; q3 = 0.0; q4 = 0.0
        bx = 1.0; bz = 0.0
        ax = 0.0; ay = 0.0; az = 0.0; accT = 0L; hasAcc = false
        mx = 0.0; my = 0.0; mz = 0.0; magT = 0L; hasMag = false; magTooStrong = false
        initialised = false; lastT = 0L; firstAccT = 0L; waitingForMag = false
        steps = 0L; skippedBeforeInit = 0L; skippedNonFinite = 0L; skippedOutOfRange = 0L; skippedZero = 0L
        skippedTimestamp = 0L; skippedGap = 0L; staleSamples = 0L; accRejections = 0L; magRejections = 0L
        saturations = 0L; stillRecoveries = 0L
    }

    /** Whether the inclination recovery acts (for tests that stop a run inside it). */
    internal val inclinationRecovering: Boolean get() = recovery.active

    /** The magnetic disturbance detector's resume ramp, 0…1 (1 without the detector). */
    internal val magneticGainFactor: Double get() = magDetector?.gainFactor ?: 1.0

    /** The rest detector's verdict of the last step (false without rest bias estimation; the offline heading smoother's). */
    internal val atRest: Boolean get() = bias.atRest

    /** The gyroscope bias estimate ω_b, rad/s, device frame, into [out] (the offline heading smoother's; allocates nothing). */
    internal fun gyroBiasInto(out: DoubleArray) {
        out[0] = bias.x; out[1] = bias.y; out[2] = bias.z
    }

    /**
     * Turns the filter round in time, for a pass over the same samples backward (the offline estimate,
     * replay/Offline.kt): the gyroscope readings of such a pass are negated, so the bias estimate and the
     * rest detector's gyroscope low-pass are negated too; the orientation, the field reference, the
     * low-passed accelerometer and the held readings stay. [timestampNs] is the time, on the new pass's
     * clock, of the last step taken: the held readings keep their age then, so one that had gone stale
     * (a stream that ended before the gyroscope's) is not used again by the new pass.
     */
    internal fun turnAround(timestampNs: Long) {
        bias.reverse()
        accT = timestampNs - (lastT - accT)
        magT = timestampNs - (lastT - magT)
        lastT = timestampNs
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
        lowPass.restart()
    }

    // Estimated up in the sensor frame, q̂* ⊗ [0, 0, 0, 1] ⊗ q̂ (the terms of eq. 25).
    private fun upX() = 2.0 * (q2 * q4 - q1 * q3)
    private fun upY() = 2.0 * (q1 * q2 + q3 * q4)
    private fun upZ() = 1.0 - 2.0 * (q2 * q2 + q3 * q3)

    private fun flags(): Long =
        (if (hasAcc) 1L else 0L) or (if (hasMag) 2L else 0L) or (if (initialised) 4L else 0L) or (if (waitingForMag) 8L else 0L) or (if (magTooStrong) 16L else 0L)

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
        recovery.start()
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
        lowPass.restart()
        recovery.arm()
        heading.restart()
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
        val wx = gx - bias.x // (eq. 49)
        val wy = gy - bias.y
        val wz = gz - bias.z
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
            bias.x += 2.0 * k * (q1 * e2 - q2 * e1 - q3 * e4 + q4 * e3)
            bias.y += 2.0 * k * (q1 * e3 + q2 * e4 - q3 * e1 - q4 * e2)
            bias.z += 2.0 * k * (q1 * e4 - q2 * e3 + q3 * e2 - q4 * e1)
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
        /** The filter's own doubles in a snapshot (q̂, b, the held readings); the units' states follow. */
        const val DOUBLES = 12
        const val STATE_DOUBLES = DOUBLES + GyroBiasEstimate.STATE_SIZE + MagneticDisturbanceDetector.STATE_SIZE +
            AccelerometerRejection.STATE_SIZE + AccelerometerLowPass.STATE_SIZE + InclinationRecovery.STATE_SIZE + HeadingCorrection.STATE_SIZE

        /** 1/√x as √x · (1/x): the square root and the division run in parallel (shorter latency than 1/√x). */
        fun invSqrt(x: Double): Double = sqrt(x) * (1.0 / x)
    }
}
