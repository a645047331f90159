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

internal class AccelerometerRejection(settings: FilterSettings) {
    private val normTolerance = settings.accNormTolerance
    private val cosAngleTolerance = cos(settings.accAngleTolerance)
    private val maxRejectionTime = settings.accMaxRejectionTime

    private var rejectedTime = 0.0
    private var recovering = false

    var rejected = false
        private set

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

    fun reset() {
        rejectedTime = 0.0
        recovering = false
        rejected = false
    }

    fun writeState(d: DoubleArray, at: Int): Int {
        d[at] = rejectedTime
        d[at + 1] = if (recovering) 1.0 else 0.0
        d[at + 2] = if (rejected) 1.0 else 0.0
        return at + STATE_SIZE
    }

    fun readState(d: DoubleArray, at: Int): Int {
        rejectedTime = d[at]
        recovering = d[at + 1] != 0.0
        rejected = d[at + 2] != 0.0
        return at + STATE_SIZE
    }

    companion object {
        const val STATE_SIZE = 3
    }
}
