/*
 * The gyroscope bias estimate ω_b (rad/s, device frame) beyond the report's drift compensation ζ
 * (which the filter's gradient step adds to the same estimate, eqs. 47–48).
 *
 * At rest (restBiasEstimation, RestDetector): the mean of the readings since rest began, then a moving
 * average over restBiasTime. In motion (motionBiasGain > 0 with headingGain > 0): the heading error the
 * heading step removes, as a rotation rate about the estimated up in the sensor frame, e = −sin δ·v̂, is
 * integrated into the bias, as the integral term of a PI observer: ω_b −= k·e·Δt, each axis limited to
 * ±motionBiasLimit; after a rest estimate the gain ramps up from 0 over motionBiasRestTime (the rest
 * estimate is the better one until the bias may have drifted away from it). (The same with the
 * accelerometer's error, â × v̂, was measured and hurts: linear acceleration leaks into it.)
 * Allocation-free.
 */
package dev.motionfusion.core.filter

internal class GyroBiasEstimate(settings: FilterSettings) {
    private val rest = if (settings.restBiasEstimation) RestDetector(settings) else null
    private val restBiasTime = settings.restBiasTime
    private val restMinTime = settings.restMinTime
    private val motionGain = settings.motionBiasGain
    private val motionRestTime = settings.motionBiasRestTime
    private val limit = settings.motionBiasLimit
    private val inclinationGain = settings.motionBiasInclinationGain
    private val leakRate = if (settings.motionBiasLeakTime > 0.0) 1.0 / settings.motionBiasLeakTime else 0.0

    // The last rest estimate (zero before one), which the motion estimate leaks back to (motionBiasLeakTime).
    private var restX = 0.0
    private var restY = 0.0
    private var restZ = 0.0

    /** ω_b, rad/s, device frame (the gradient step's ζ term adds to it too). */
    var x = 0.0
    var y = 0.0
    var z = 0.0

    // While held (a disturbed field): the motion estimate learns into this shadow instead, which is taken
    // (commit) or dropped (release) when the hold ends.
    var holding = false
        private set
    private var sx = 0.0
    private var sy = 0.0
    private var sz = 0.0

    fun hold() { holding = true; sx = x; sy = y; sz = z }
    fun commit() { holding = false; x = sx; y = sy; z = sz }
    fun release() { holding = false }

    // Time since the rest estimate last acted, s (infinite before it has).
    private var sinceRest = Double.POSITIVE_INFINITY

    /** Whether the motion estimate acts from the heading error (motionBiasGain ≠ 0). */
    val inMotion = motionGain != 0.0

    /** Whether the motion estimate acts from the inclination error (motionBiasInclinationGain ≠ 0). */
    val fromInclination = inclinationGain != 0.0

    /** The rest detector's verdict of the last step (false without rest bias estimation). */
    val atRest: Boolean get() = rest?.atRest ?: false

    /** The rest estimate: one gyroscope step of [dt] s with the reading [gx], [gy], [gz] and, when [accOk], the accelerometer's. */
    fun update(dt: Double, gx: Double, gy: Double, gz: Double, accOk: Boolean, ax: Double, ay: Double, az: Double) {
        if (rest != null && rest.update(dt, gx, gy, gz, accOk, ax, ay, az)) {
            // Mean of the readings since rest began, then a moving average over restBiasTime.
            val k = dt / minOf(restBiasTime, rest.restTime - restMinTime + dt)
            x += k * (gx - x); y += k * (gy - y); z += k * (gz - z)
            restX = x; restY = y; restZ = z
            holding = false
            sinceRest = 0.0
        } else if (motionGain != 0.0 || inclinationGain != 0.0) {
            sinceRest += dt
        }
    }

    /** The motion estimate after a heading step of weight [dt] s that found the error sin δ = [sinDelta]; ([upX], [upY], [upZ]) the estimated up. */
    fun motion(dt: Double, sinDelta: Double, upX: Double, upY: Double, upZ: Double) {
        val ramp = if (sinceRest < motionRestTime) sinceRest / motionRestTime else 1.0
        val k = motionGain * ramp * dt * sinDelta
        if (leakRate != 0.0) {
            val l = minOf(1.0, leakRate * dt)
            x -= l * (x - restX); y -= l * (y - restY); z -= l * (z - restZ)
        }
        if (holding) {
            sx = (sx + k * upX).coerceIn(-limit, limit)
            sy = (sy + k * upY).coerceIn(-limit, limit)
            sz = (sz + k * upZ).coerceIn(-limit, limit)
            return
        }
        x = (x + k * upX).coerceIn(-limit, limit)
        y = (y + k * upY).coerceIn(-limit, limit)
        z = (z + k * upZ).coerceIn(-limit, limit)
    }

    /**
     * The gain (rad/s²) with which the inclination step's correction enters the bias in motion (the report's ζ of
     * eqs. 47–48, applied to the accelerometer-only step): the normalised correction ω_ε, a rate about a horizontal
     * axis, so it never changes the bias about the vertical and no magnetic disturbance enters it; ramped up after
     * a rest estimate as the heading's.
     */
    fun inclinationGain(): Double {
        val ramp = if (sinceRest < motionRestTime) sinceRest / motionRestTime else 1.0
        return inclinationGain * ramp
    }

    /** For a pass backward in time (gyroscope readings negated): the estimate and the rest detector's gyroscope low-pass are negated. */
    fun reverse() {
        x = -x; y = -y; z = -z
        rest?.reverse()
    }

    fun reset() {
        x = 0.0; y = 0.0; z = 0.0
        restX = 0.0; restY = 0.0; restZ = 0.0
        holding = false; sx = 0.0; sy = 0.0; sz = 0.0
        sinceRest = Double.POSITIVE_INFINITY
        rest?.reset()
    }

    fun writeState(d: DoubleArray, at: Int): Int {
        d[at] = x; d[at + 1] = y; d[at + 2] = z
        d[at + 3] = sinceRest
        d[at + 4] = restX; d[at + 5] = restY; d[at + 6] = restZ
        d[at + 7] = if (holding) 1.0 else 0.0; d[at + 8] = sx; d[at + 9] = sy; d[at + 10] = sz
        return rest?.writeState(d, at + 11) ?: (at + STATE_SIZE)
    }

    fun readState(d: DoubleArray, at: Int): Int {
        x = d[at]; y = d[at + 1]; z = d[at + 2]
        sinceRest = d[at + 3]
        restX = d[at + 4]; restY = d[at + 5]; restZ = d[at + 6]
        holding = d[at + 7] != 0.0; sx = d[at + 8]; sy = d[at + 9]; sz = d[at + 10]
        return rest?.readState(d, at + 11) ?: (at + STATE_SIZE)
    }

    companion object {
        const val STATE_SIZE = 11 + RestDetector.STATE_SIZE
    }
}
