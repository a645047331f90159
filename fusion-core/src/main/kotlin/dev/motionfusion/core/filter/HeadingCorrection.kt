/*
 * The gain of the heading step (beyond the report; headingGain > 0): the magnetometer corrects heading
 * in a step of its own after the IMU step, by the fraction headingGain·Δt of the heading error per step.
 *
 * Fast convergence (headingRecoveryTime): for that long after the start, after a saturated gyroscope
 * reading and after a new magnetic reference, while the heading is off (from an error above 2° until it
 * is below 0.5°), the gain is at least 1/t, t the time since then (the mean of the errors). The caller
 * multiplies in the magnetic disturbance detector's resume ramp. Units s, 1/s. Allocation-free.
 */
package dev.motionfusion.core.filter

import kotlin.math.abs

internal class HeadingCorrection(settings: FilterSettings) : Stage<HeadingCorrection.State> {
    private val gain = settings.headingGain ?: 0.0
    private val recoveryTime = settings.headingRecoveryTime ?: 0.0 // off: the clock is never below it

    /** False with headingGain off: the magnetometer enters the report's MARG gradient instead. */
    val enabled = settings.headingGain != null

    // Time since the start, a saturation or the last new magnetic reference, s.
    private var clock = 0.0

    // Whether the fast convergence acts: from a heading error above 2° until it is below 0.5°.
    private var off = true

    /** Fast convergence starts again, as at the start (the heading may be off in any direction). */
    fun restart() {
        clock = 0.0
        off = true
    }

    /** A new magnetic reference: the time of the fast convergence starts again. */
    fun newReference() {
        clock = 0.0
    }

    /** The gain (1/s) of a step of [dt] s, times [factor] (the resume ramp after a disturbance, else 1). */
    fun gain(dt: Double, factor: Double): Double {
        clock += dt
        val k = if (clock < recoveryTime && off) maxOf(gain, 1.0 / clock) else gain
        return k * factor
    }

    /** The heading error the step found, as sin δ: ends or starts the fast convergence. */
    fun observe(sinDelta: Double) {
        off = abs(sinDelta) > (if (off) SIN_RECOVERY_DONE else SIN_RECOVERY_ERROR)
    }

    override fun reset() = restart()

    /** The time since the start, a saturation or a new reference, and whether the fast convergence acts. */
    data class State(val clock: Double, val off: Boolean)

    override fun state() = State(clock, off)

    override fun restore(state: State) {
        clock = state.clock
        off = state.off
    }

    companion object {
        /** sin of the heading errors at which the fast convergence starts (2°) and ends (0.5°). */
        val SIN_RECOVERY_ERROR = kotlin.math.sin(2.0 * Math.PI / 180.0)
        val SIN_RECOVERY_DONE = kotlin.math.sin(0.5 * Math.PI / 180.0)
    }
}
