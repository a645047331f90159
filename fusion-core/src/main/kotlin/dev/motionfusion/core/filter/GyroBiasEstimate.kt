/*
 * The gyroscope bias estimate ω_b (rad/s, device frame): the report's drift compensation ζ (eqs. 47–48,
 * whose term the MARG step hands in: [GyroBiasEstimate.drift]) and, beyond the report, estimates at rest
 * and in motion. This class is the bias's one writer.
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

internal class GyroBiasEstimate(settings: FilterSettings) : Stage<GyroBiasEstimate.State> {
    private val rest = if (settings.restBiasEstimation) RestDetector(settings) else null
    private val zeta = settings.zeta ?: 0.0
    private val restBiasTime = settings.restBiasTime
    private val motionGain = settings.motionBiasGain ?: 0.0
    private val motionRestTime = settings.motionBiasRestTime
    private val limit = settings.motionBiasLimit

    /** ω_b, rad/s, device frame. */
    var x = 0.0
        private set
    var y = 0.0
        private set
    var z = 0.0
        private set

    /** Whether the report's drift compensation acts (ζ on). */
    val drifts = settings.zeta != null

    // Time since the rest estimate last acted, s (infinite before it has).
    private var sinceRest = Double.POSITIVE_INFINITY

    /** Whether the motion estimate acts (motionBiasGain on). */
    val inMotion = settings.motionBiasGain != null

    /** The rest detector's verdict of the last step (false without rest bias estimation). */
    val atRest: Boolean get() = rest?.atRest ?: false

    /** The rest estimate: one gyroscope step of [dt] s with the reading [gx], [gy], [gz] and, when [accOk], the accelerometer's. */
    fun update(dt: Double, gx: Double, gy: Double, gz: Double, accOk: Boolean, ax: Double, ay: Double, az: Double) {
        if (rest != null && rest.update(dt, gx, gy, gz, accOk, ax, ay, az)) {
            // The mean of the readings since the rest began (restMinTime or more before it was declared: one step's
            // reading is noise; RestDetector.meanX), then a moving average over restBiasTime.
            if (rest.declared || (rest.plausible && rest.plausibleTime <= restBiasTime)) {
                x = rest.meanX; y = rest.meanY; z = rest.meanZ
            } else {
                val k = dt / restBiasTime
                x += k * (gx - x); y += k * (gy - y); z += k * (gz - z)
            }
            sinceRest = 0.0
        } else if (inMotion) {
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

    /**
     * The report's drift compensation (eqs. 47–48) in a MARG step of [dt] s at the estimate q̂ = ([q1]..[q4]) with
     * the normalised gradient q̇_ε = ([e1]..[e4]): ω_ε = 2 q̂* ⊗ q̇_ε, ω_b += ζ ω_ε Δt. Returns ζΔt, for the step's
     * own share of the change.
     */
    fun drift(dt: Double, q1: Double, q2: Double, q3: Double, q4: Double, e1: Double, e2: Double, e3: Double, e4: Double): Double {
        val k = zeta * dt
        x += 2.0 * k * (q1 * e2 - q2 * e1 - q3 * e4 + q4 * e3)
        y += 2.0 * k * (q1 * e3 + q2 * e4 - q3 * e1 - q4 * e2)
        z += 2.0 * k * (q1 * e4 - q2 * e3 + q3 * e2 - q4 * e1)
        return k
    }

    /** For a pass backward in time (gyroscope readings negated): the estimate and the rest detector's gyroscope low-pass are negated. */
    fun reverse() {
        x = -x; y = -y; z = -z
        rest?.reverse()
    }

    override fun reset() {
        x = 0.0; y = 0.0; z = 0.0
        sinceRest = Double.POSITIVE_INFINITY
        rest?.reset()
    }

    /** ω_b, the time since the rest estimate acted, and the rest detector's state (null without it). */
    data class State(val x: Double, val y: Double, val z: Double, val sinceRest: Double, val rest: RestDetector.State?)

    override fun state() = State(x, y, z, sinceRest, rest?.state())

    override fun restore(state: State) {
        x = state.x; y = state.y; z = state.z
        sinceRest = state.sinceRest
        if (rest != null) rest.restore(state.rest!!)
    }
}
