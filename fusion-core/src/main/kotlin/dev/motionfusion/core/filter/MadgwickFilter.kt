/*
 * The Madgwick orientation filter: S. O. H. Madgwick, "An efficient orientation filter for
 * inertial and inertial/magnetic sensor arrays", University of Bristol, 2010 (the "report"), with the
 * mechanisms beyond it that FilterSettings turns on.
 *
 * Frames. Inputs in the Android device frame (x right, y up along the screen, z out of the
 * screen). The estimate q̂ = [w, x, y, z] (Hamilton) is the sensor's orientation in the report's
 * North-West-Up earth frame (x magnetic north, y west, z up): v_earth = q̂ ⊗ v_sensor ⊗ q̂*.
 * Readers convert it to FilterSettings.outputFrame (ENU by default, Android's world).
 *
 * Units. Gyroscope rad/s, accelerometer m/s² (specific force, +g on the up axis at rest, as
 * TYPE_ACCELEROMETER), magnetometer µT, timestamps in ns (SensorEvent.timestamp), settings in s.
 *
 * Composition. The filter is its stages (Stage.kt: own settings, own state as a data class, reset), which
 * share one Step, the values of the gyroscope step under way; one gyroscope step runs them in this order:
 *   SampleGate            validation, pairing and staleness, the start, gaps, the counts (SampleGate.kt)
 *   saturation            a clipped gyroscope reading: low-pass, inclination and heading start again
 *   GyroBiasEstimate      the bias ω_b at rest (RestDetector), then in motion after the heading step, and ζ
 *   HardIronEstimate      the magnetometer's offset, learnt from the field's turning against the bias-corrected
 *                         rate; taken off each reading as it is held (HardIronEstimate.kt)
 *   checks                which readings enter: AccelerometerRejection, MagneticDisturbanceDetector, and
 *                         MagneticTrust, which weighs the heading gain (Check)
 *   InclinationRecovery   a still error arms it; then the step gain β
 *   AccelerometerLowPass  the accelerometer low-passed in a quasi-inertial frame, what the steps use
 *   MadgwickSteps         the report's MARG, IMU or gyroscope-only step (MadgwickSteps.kt), then
 *   HeadingCorrection     the heading step's gain (headingGain > 0) with its fast convergence
 * state()/restore() hold all of it (FilterState, the stages' states composed), so a run stopped and
 * resumed continues bit for bit (StopResumeTest). The report's equations hold exactly with
 * FilterSettings.report().
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.WorldFrame

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
    private val s = Step()
    private val gate = SampleGate(settings, s)
    private val bias = GyroBiasEstimate(settings)
    private val estimate = MadgwickSteps(bias)
    private val lowPass = AccelerometerLowPass(settings)
    private val recovery = InclinationRecovery(settings)
    private val heading = HeadingCorrection(settings)
    private val accRejection = if (settings.accRejection) AccelerometerRejection(settings) else null
    private val magDetector = if (settings.magDisturbanceRejection) MagneticDisturbanceDetector(settings) else null
    private val magTrust = if (settings.magTrustSpread != null) MagneticTrust(settings) else null
    private val hardIron = if (settings.hardIronThreshold != null && settings.mode == FilterMode.MARG) HardIronEstimate(settings) else null

    /** Which readings enter each step, in this order (a new detector: one more line here). */
    private var checks: Array<Check<*>> = listOfNotNull<Check<*>>(
        accRejection,
        magDetector,
        magTrust,
    ).toTypedArray()

    /** Adds [extra] checks after the filter's own, before its first sample (a detector tried out before it joins the list above). */
    internal fun withChecks(vararg extra: Check<*>): MadgwickFilter {
        checks += extra
        return this
    }

    private val firstSample = settings.initialisation == Initialisation.FIRST_SAMPLE
    private val scratch = DoubleArray(4)

    // c, the change from the report's NWU to the output frame: q_out = c ⊗ q̂.
    private val outputChange = WorldFrame.NWU.quaternionTo(settings.outputFrame)

    /** True once the filter has an orientation. Before that, [orientation] is the identity (of the output frame). */
    public val isInitialised: Boolean get() = gate.isInitialised

    /** Holds an accelerometer sample (m/s², device frame) for the next gyroscope steps. */
    public fun updateAccelerometer(timestampNs: Long, x: Double, y: Double, z: Double) {
        gate.holdAccelerometer(timestampNs, x, y, z)
    }

    /** Holds a magnetometer sample (µT, device frame) for the next gyroscope steps; ignored in IMU mode. */
    public fun updateMagnetometer(timestampNs: Long, x: Double, y: Double, z: Double) {
        val h = hardIron
        if (h == null) return gate.holdMagnetometer(timestampNs, x, y, z)
        h.hold(x, y, z)
        if (h.applied) gate.holdMagnetometer(timestampNs, x - h.x, y - h.y, z - h.z)
        else gate.holdMagnetometer(timestampNs, x, y, z)
    }

    /**
     * One filter step on a gyroscope sample (rad/s, device frame) with the held accelerometer and
     * magnetometer samples (see the pairing rule in SampleGate.kt). The step length is the time
     * since the previous gyroscope sample; a timestamp that does not advance, or a gap longer than
     * maxGap, is counted and not integrated.
     */
    public fun updateGyroscope(timestampNs: Long, x: Double, y: Double, z: Double) {
        when (gate.admit(timestampNs, x, y, z)) {
            Admission.SKIP -> return
            Admission.START -> return start(timestampNs)
            Admission.STEP -> {}
        }
        val dt = s.dt
        if (gate.saturated || gate.afterGap) rotationUnknown()
        // The estimated up, for the checks and the inclination recovery (the report's filter has neither).
        if (recovery.usesUp || checks.isNotEmpty()) { s.ux = estimate.upX(); s.uy = estimate.upY(); s.uz = estimate.upZ() }
        bias.update(dt, x, y, z, s.accOk, s.ax, s.ay, s.az)
        s.wx = x - bias.x; s.wy = y - bias.y; s.wz = z - bias.z
        s.useAcc = s.accOk; s.useMag = s.magOk; s.headingFactor = 1.0; s.biasFactor = 1.0; s.newMagReference = false
        val h = hardIron
        if (h != null) {
            val jumped = h.update(s)
            // The held reading with the offset of now; when it jumped, what was learnt of the field starts again.
            if (h.applied) { s.mx = h.rawX - h.x; s.my = h.rawY - h.y; s.mz = h.rawZ - h.z }
            if (jumped) {
                s.newMagReference = true
                magDetector?.forgetReference()
            }
        }
        for (check in checks) check.check(s)
        if (s.newMagReference) heading.newReference()
        if (recovery.stillError(dt, s.wx, s.wy, s.wz, s.accOk, s.ax, s.ay, s.az, s.ux, s.uy, s.uz)) lowPass.restart()
        var cx = s.ax
        var cy = s.ay
        var cz = s.az
        if (lowPass.enabled) {
            lowPass.update(dt, s.wx, s.wy, s.wz, s.accOk, s.ax, s.ay, s.az)
            cx = lowPass.x; cy = lowPass.y; cz = lowPass.z
        }
        val beta = recovery.beta(dt, s.useAcc, s.ax, s.ay, s.az, cx, cy, cz, s.ux, s.uy, s.uz)
        when {
            s.useMag && !heading.enabled -> estimate.marg(s, beta, s.useAcc, cx, cy, cz)
            s.useAcc -> estimate.imu(s, beta, cx, cy, cz)
            else -> estimate.gyro(s, beta)
        }
        if (s.useMag && heading.enabled) {
            val f = s.headingFactor
            val sinDelta = estimate.heading(dt * heading.gain(dt, f), s.mx, s.my, s.mz)
            heading.observe(sinDelta)
            if (bias.inMotion) bias.motion(dt * f * s.biasFactor, sinDelta, estimate.upX(), estimate.upY(), estimate.upZ())
        }
    }

    /** The first step ([Admission.START]): the orientation from the held readings (FIRST_SAMPLE) or the identity. */
    private fun start(t: Long) {
        if (firstSample) estimate.startFrom(s)
        gate.started(t)
        recovery.start()
    }

    /**
     * A gyroscope reading clipped at the sensor's range (gyroSaturation), whose integrated rotation is
     * short of the true one by an unknown amount, or the first step after a gap longer than maxGap, over
     * which nothing was integrated: the estimate can be off in any direction. The low-passed
     * accelerometer (whose frame turned with that rotation) starts again from the next reading,
     * inclination recovery is armed (inclinationRecoveryBeta) and fast heading convergence starts again
     * (headingRecoveryTime).
     */
    private fun rotationUnknown() {
        hardIron?.dropWindow()
        lowPass.restart()
        recovery.arm()
        heading.restart()
    }

    /**
     * A reading of [stream] at [timestampNs], in its SI unit: the gyroscope's, accelerometer's or
     * magnetometer's update; any other stream is no input of the filter. The one dispatch from a
     * stream to the filter (the replay of a recording and the app's live pipeline use it). True for
     * a gyroscope reading, the one that steps the filter.
     */
    public fun update(stream: SessionStream, timestampNs: Long, x: Double, y: Double, z: Double): Boolean = when (stream) {
        SessionStream.GYROSCOPE -> { updateGyroscope(timestampNs, x, y, z); true }
        SessionStream.ACCELEROMETER -> { updateAccelerometer(timestampNs, x, y, z); false }
        SessionStream.MAGNETOMETER -> { updateMagnetometer(timestampNs, x, y, z); false }
        else -> false
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
        gate.dropMagnetometer()
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
        if (!gate.isInitialised) {
            out[offset] = 1.0; out[offset + 1] = 0.0; out[offset + 2] = 0.0; out[offset + 3] = 0.0
            return
        }
        // q_out = c ⊗ q̂ (Hamilton product with the fixed frame change c).
        outputChange.timesInto(estimate.q1, estimate.q2, estimate.q3, estimate.q4, out, offset)
    }

    /** A copy of the current flags, bias estimate and counters (allocates; not for every sample). */
    public fun diagnostics(): FilterDiagnostics = FilterDiagnostics(
        initialised = gate.isInitialised,
        gyroBias = Vector3(bias.x, bias.y, bias.z),
        atRest = bias.atRest,
        magneticDisturbance = (magDetector?.disturbed ?: false) || gate.magneticTooStrong || (magTrust?.holds ?: false),
        accelerometerRejected = accRejection?.rejected ?: false,
        gyroscopeSteps = gate.steps,
        skippedBeforeInit = gate.skippedBeforeInit,
        skippedNonFinite = gate.skippedNonFinite + estimate.dropped,
        skippedOutOfRange = gate.skippedOutOfRange,
        skippedZero = gate.skippedZero,
        skippedTimestamp = gate.skippedTimestamp,
        skippedGap = gate.skippedGap,
        staleSamples = gate.staleSamples,
        accelerometerRejections = accRejection?.rejections ?: 0L,
        magneticRejections = gate.tooStrong + (magDetector?.rejections ?: 0L),
        gyroscopeSaturations = gate.saturations,
        magnetometerOffset = hardIron?.takeIf { it.applied }?.let { Vector3(it.x, it.y, it.z) } ?: Vector3.ZERO,
    )

    /** The complete state, for [restore] (allocates; not for every sample). */
    public fun state(): FilterState = FilterState(
        settings, gate.state(), estimate.state(), bias.state(), lowPass.state(), recovery.state(), heading.state(),
        hardIron?.state(), checks.map { it.state() },
    )

    /**
     * Restores a state taken by [state].
     * @throws IllegalArgumentException if the state was taken under other settings.
     */
    public fun restore(state: FilterState) {
        require(state.settings == settings && state.checks.size == checks.size) { "state taken under other settings" }
        gate.restore(state.gate)
        estimate.restore(state.estimate)
        bias.restore(state.bias)
        lowPass.restore(state.lowPass)
        recovery.restore(state.recovery)
        heading.restore(state.heading)
        state.hardIron?.let { hardIron?.restore(it) }
        for (i in checks.indices) checks[i].restoreAny(state.checks[i])
    }

    /** Back to the state of a new filter with the same settings (every stage's state and the counters included). */
    internal fun reset() {
        gate.reset()
        estimate.reset()
        bias.reset()
        lowPass.reset()
        recovery.reset()
        heading.reset()
        hardIron?.reset()
        for (check in checks) check.reset()
    }

    /** Whether the inclination recovery acts (for tests that stop a run inside it). */
    internal val inclinationRecovering: Boolean get() = recovery.active

    /** The magnetic trust's factor of the last step, 0…1 (1 without it). */
    internal val magneticTrust: Double get() = magTrust?.trust ?: 1.0

    /** The magnetic disturbance detector's resume ramp, 0…1 (1 without the detector). */
    internal val magneticGainFactor: Double get() = magDetector?.gainFactor ?: 1.0

    /** The gyroscope steps taken so far (FilterDiagnostics.gyroscopeSteps, without allocating): the replay's FieldPersistence. */
    internal val stepsTaken: Long get() = gate.steps

    /** The last step's length, s, and whether it was the first after a gap (its rotation unknown). */
    internal val lastStepDt: Double get() = s.dt
    internal val lastStepAfterGap: Boolean get() = gate.afterGap

    /** The rest detector's verdict of the last step (false without rest bias estimation; the offline heading smoother's). */
    internal val atRest: Boolean get() = bias.atRest

    /** The magnetometer reading [m] (µT, device frame) as a step now takes it, its hard-iron offset taken off, into [out] (the offline passes'). */
    internal fun fieldSeenInto(m: DoubleArray, out: DoubleArray) {
        val h = hardIron
        val take = h != null && h.takesOff(m[0], m[1], m[2])
        out[0] = if (take) m[0] - h!!.x else m[0]
        out[1] = if (take) m[1] - h!!.y else m[1]
        out[2] = if (take) m[2] - h!!.z else m[2]
    }

    /** The gyroscope bias estimate ω_b, rad/s, device frame, into [out] (the offline heading smoother's; allocates nothing). */
    internal fun gyroBiasInto(out: DoubleArray) {
        out[0] = bias.x; out[1] = bias.y; out[2] = bias.z
    }

    /**
     * Turns the filter round in time, for a pass over the same samples backward (the offline estimate,
     * filter/offline): the gyroscope readings of such a pass are negated, so the bias estimate and the
     * rest detector's gyroscope low-pass are negated too (the hard-iron estimate's open window is dropped; its
     * equation holds backward as it does forward); the orientation, the field reference, the
     * low-passed accelerometer and the held readings stay. [timestampNs] is the time, on the new pass's
     * clock, of the last step taken: the held readings keep their age then, so one that had gone stale
     * (a stream that ended before the gyroscope's) is not used again by the new pass.
     */
    internal fun turnAround(timestampNs: Long) {
        bias.reverse()
        hardIron?.dropWindow()
        gate.turnAround(timestampNs)
    }

    /**
     * Takes [q] ([w, x, y, z] in settings.outputFrame, unit) as the estimate, everything else kept, for a pass
     * of the offline estimate that goes on across a gap (filter/offline): there the other pass's orientation,
     * which has run through the samples beyond the gap, is better than one carried over it. The low-passed
     * accelerometer, held in the frame of the old estimate, starts again from the next reading.
     */
    internal fun takeOrientation(q: DoubleArray) {
        outputChange.conjugate().timesInto(q[0], q[1], q[2], q[3], scratch, 0)
        estimate.take(scratch[0], scratch[1], scratch[2], scratch[3])
        lowPass.restart()
    }
}
