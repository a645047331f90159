/*
 * Accelerometer rejection (beyond the report).
 *
 * The accelerometer measures gravity only when the sensor does not accelerate. A reading whose
 * magnitude departs from standard gravity, or whose direction departs from the filter's estimated
 * up, carries linear acceleration and is left out of the correction. If readings stay rejected for
 * longer than accMaxRejectionTime, the estimate itself is more likely wrong than the accelerometer:
 * rejection is suspended until a reading agrees with the estimate again. Units: m/s², rad, s.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.STANDARD_GRAVITY
import kotlin.math.abs
import kotlin.math.cos
import kotlin.math.sqrt

internal class AccelerometerRejection(settings: FilterSettings) : Check<AccelerometerRejection.State> {
    private val normTolerance = settings.accNormTolerance
    private val cosAngleTolerance = cos(settings.accAngleTolerance)
    private val maxRejectionTime = settings.accMaxRejectionTime

    private var rejectedTime = 0.0
    private var recovering = false

    var rejected = false
        private set

    /** Steps whose reading was rejected. */
    var rejections = 0L
        private set

    /** The held reading of [s] enters the step unless [accept] rejects it (the direction against the estimated up). */
    override fun check(s: Step) {
        if (!s.useAcc) return
        val n = sqrt(s.ax * s.ax + s.ay * s.ay + s.az * s.az)
        if (!accept(s.dt, n, (s.ax * s.ux + s.ay * s.uy + s.az * s.uz) / n)) {
            rejections++
            s.useAcc = false
        }
    }

    /**
     * Classifies one reading of magnitude [norm] (m/s²) whose direction has cosine [cosUp] with the
     * estimated up direction, after [dt] s. Returns true when the reading may be used.
     */
    fun accept(dt: Double, norm: Double, cosUp: Double): Boolean {
        val agrees = abs(norm - STANDARD_GRAVITY) <= normTolerance && cosUp >= cosAngleTolerance
        if (agrees) {
            rejectedTime = 0.0
            recovering = false
        } else if (!recovering) {
            rejectedTime += dt
            recovering = rejectedTime > maxRejectionTime
        }
        rejected = !agrees && !recovering
        return !rejected
    }

    override fun reset() = restore(NEW)

    /** The time rejected, whether the rejection is suspended, the verdict and the count. */
    data class State(val rejectedTime: Double, val recovering: Boolean, val rejected: Boolean, val rejections: Long)

    override fun state() = State(rejectedTime, recovering, rejected, rejections)

    override fun restore(state: State) {
        rejectedTime = state.rejectedTime
        recovering = state.recovering
        rejected = state.rejected
        rejections = state.rejections
    }

    private companion object {
        val NEW = State(0.0, false, false, 0L)
    }
}
