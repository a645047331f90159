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
    private val motionGain = settings.motionBiasGain
    private val motionRestTime = settings.motionBiasRestTime
    private val limit = settings.motionBiasLimit

    /** ω_b, rad/s, device frame (the gradient step's ζ term adds to it too). */
    var x = 0.0
    var y = 0.0
    var z = 0.0

    // Time since the rest estimate last acted, s (infinite before it has).
    private var sinceRest = Double.POSITIVE_INFINITY

    /** Whether the motion estimate acts (motionBiasGain ≠ 0). */
    val inMotion = motionGain != 0.0

    /** The rest detector's verdict of the last step (false without rest bias estimation). */
    val atRest: Boolean get() = rest?.atRest ?: false

    /** The rest estimate: one gyroscope step of [dt] s with the reading [gx], [gy], [gz] and, when [accOk], the accelerometer's. */
    fun update(dt: Double, gx: Double, gy: Double, gz: Double, accOk: Boolean, ax: Double, ay: Double, az: Double) {
        if (rest != null && rest.update(dt, gx, gy, gz, accOk, ax, ay, az)) {
            // Mean of the readings since rest began, then a moving average over restBiasTime.
            val k = dt / minOf(restBiasTime, rest.restTime - rest.acceptedAfter + dt)
            x += k * (gx - x); y += k * (gy - y); z += k * (gz - z)
            sinceRest = 0.0
        } else if (motionGain != 0.0) {
            sinceRest += dt
        }
    }

    /** The motion estimate after a heading step of weight [dt] s that found the error sin δ = [sinDelta]; ([upX], [upY], [upZ]) the estimated up. */
    fun motion(dt: Double, sinDelta: Double, upX: Double, upY: Double, upZ: Double) {
        val ramp = if (sinceRest < motionRestTime) sinceRest / motionRestTime else 1.0
        val k = motionGain * ramp * dt * sinDelta
        x = (x + k * upX).coerceIn(-limit, limit)
        y = (y + k * upY).coerceIn(-limit, limit)
        z = (z + k * upZ).coerceIn(-limit, limit)
    }

    /** For a pass backward in time (gyroscope readings negated): the estimate and the rest detector's gyroscope low-pass are negated. */
    fun reverse() {
        x = -x; y = -y; z = -z
        rest?.reverse()
    }

    fun reset() {
        x = 0.0; y = 0.0; z = 0.0
        sinceRest = Double.POSITIVE_INFINITY
        rest?.reset()
    }

    fun writeState(d: DoubleArray, at: Int): Int {
        d[at] = x; d[at + 1] = y; d[at + 2] = z
        d[at + 3] = sinceRest
        return rest?.writeState(d, at + 4) ?: (at + STATE_SIZE)
    }

    fun readState(d: DoubleArray, at: Int): Int {
        x = d[at]; y = d[at + 1]; z = d[at + 2]
        sinceRest = d[at + 3]
        return rest?.readState(d, at + 4) ?: (at + STATE_SIZE)
    }

    companion object {
        const val STATE_SIZE = 4 + RestDetector.STATE_SIZE
    }
}
