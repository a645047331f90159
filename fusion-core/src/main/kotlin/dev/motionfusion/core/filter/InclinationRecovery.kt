/*
 * Inclination recovery after a large error (beyond the report; inclinationRecoveryBeta > 0).
 *
 * Armed at the start, by a saturated gyroscope reading, and by a still phone whose accelerometer
 * disagrees with the estimate: once armed, the accelerometer is trusted again when its magnitude has
 * stayed within accNormTolerance of standard gravity for accTrustTime; then the step gain is
 * inclinationRecoveryBeta until the reading the step uses (low-passed with accLowPassTime) is within 1°
 * of the estimated up, for at most 10 s (linear acceleration may keep it further); then β again and the
 * recovery is over. Sensor frame, SI units, s. Allocation-free.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.STANDARD_GRAVITY
import kotlin.math.abs
import kotlin.math.sqrt

internal class InclinationRecovery(settings: FilterSettings) : Stage<InclinationRecovery.State> {
    private val beta = settings.beta
    private val recovers = settings.inclinationRecoveryBeta != null

    /** Whether [stillError] and [beta] read the estimated up (only with inclinationRecoveryBeta). */
    val usesUp: Boolean get() = recovers
    private val recoveryBeta = settings.inclinationRecoveryBeta ?: 0.0
    private val accTrustTime = settings.accTrustTime
    private val accNormTolerance = settings.accNormTolerance
    private val cosRecoveryAngle = settings.recoveryAngle?.takeIf { recovers }?.let { kotlin.math.cos(it) } ?: 2.0 // 2: never
    private val recoveryGyro2 = settings.recoveryGyroThreshold * settings.recoveryGyroThreshold
    private val recoveryStillTime = settings.recoveryStillTime
    private val stillAccThreshold = settings.restAccThreshold

    // How long the phone has been near-still with a trustworthy accelerometer, s (recovery after any large error).
    private var stillTime = 0.0

    /** Set at the start and by a saturated gyroscope reading or a still error, cleared once inclination has re-converged. */
    var active = false
        private set

    // How long the accelerometer magnitude has stayed near gravity, s.
    private var accTrusted = 0.0

    /** Times a still error armed the recovery. */
    var stillRecoveries = 0L
        private set

    /** The start: inclination may be anything (an identity start, or a first reading taken in motion). */
    fun start() {
        active = true
    }

    /** A saturated gyroscope reading: the estimate may be off in any direction; trust is learnt again. */
    fun arm() {
        active = true
        accTrusted = 0.0
    }

    /**
     * Recovery after any large error (recoveryAngle > 0), checked while no recovery runs: while the phone
     * is near-still (bias-corrected rate [wx], [wy], [wz] below recoveryGyroThreshold) and the reading
     * [ax], [ay], [az] has a magnitude within restAccThreshold of standard gravity, the reading is gravity
     * within a fraction of a degree. Once that has held for recoveryStillTime, an estimated up ([upX],
     * [upY], [upZ], unit) further than recoveryAngle from the reading means the estimate was put off (an
     * impact, a shake, a fall: motions that need not reach the gyroscope's range): the recovery acts at
     * once (the accelerometer counts as trusted) and true is returned, so the caller starts the low-passed
     * accelerometer, which went through the same motion, again. A few multiplications and one square root.
     */
    fun stillError(
        dt: Double, wx: Double, wy: Double, wz: Double, accOk: Boolean,
        ax: Double, ay: Double, az: Double, upX: Double, upY: Double, upZ: Double,
    ): Boolean {
        if (cosRecoveryAngle > 1.0 || active) return false
        if (!accOk || wx * wx + wy * wy + wz * wz >= recoveryGyro2) {
            stillTime = 0.0
            return false
        }
        val n = sqrt(ax * ax + ay * ay + az * az)
        if (abs(n - STANDARD_GRAVITY) >= stillAccThreshold) {
            stillTime = 0.0
            return false
        }
        stillTime += dt
        if (stillTime >= recoveryStillTime && ax * upX + ay * upY + az * upZ < cosRecoveryAngle * n) {
            active = true
            accTrusted = accTrustTime
            stillTime = 0.0
            stillRecoveries++
            return true
        }
        return false
    }

    /**
     * The step gain β for a step of [dt] s: inclinationRecoveryBeta while the recovery acts, else β.
     * [withAcc]: the step uses the accelerometer, raw reading [ax], [ay], [az]; [cx], [cy], [cz] the
     * reading the step uses; [upX], [upY], [upZ] the estimated up.
     */
    fun beta(
        dt: Double, withAcc: Boolean, ax: Double, ay: Double, az: Double,
        cx: Double, cy: Double, cz: Double, upX: Double, upY: Double, upZ: Double,
    ): Double {
        if (!recovers || !active) return beta
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
        if (accTrusted < accTrustTime + MAX_RECOVERY_TIME && cx * upX + cy * upY + cz * upZ < COS_RECOVERY_DONE * sqrt(cx * cx + cy * cy + cz * cz)) return recoveryBeta
        active = false
        return beta
    }

    override fun reset() = restore(NEW)

    /** The still time, whether the recovery acts, the time the accelerometer has been trusted, and the count of still errors. */
    data class State(val stillTime: Double, val active: Boolean, val accTrusted: Double, val stillRecoveries: Long)

    override fun state() = State(stillTime, active, accTrusted, stillRecoveries)

    override fun restore(state: State) {
        stillTime = state.stillTime
        active = state.active
        accTrusted = state.accTrusted
        stillRecoveries = state.stillRecoveries
    }

    companion object {
        private val NEW = State(0.0, false, 0.0, 0L)

        /** The recovery ends within 1° of the accelerometer, or after 10 s of acting. */
        val COS_RECOVERY_DONE = kotlin.math.cos(1.0 * Math.PI / 180.0)
        const val MAX_RECOVERY_TIME = 10.0
    }
}
