/*
 * Rest detection for the gyroscope bias estimate (beyond the report).
 *
 * Inputs in the Android device frame, SI units (rad/s, m/s², s). The sensor is at rest when, for
 * at least restMinTime, the gyroscope stays within restGyroThreshold of its low-passed value, that
 * low-passed value stays within restGyroThreshold of zero, and the accelerometer stays within
 * restAccThreshold of its low-passed value. Allocation-free; state is primitive fields.
 */
package dev.motionfusion.core.filter

internal class RestDetector(settings: FilterSettings) : Stage<RestDetector.State> {
    private val gyroThreshold2 = settings.restGyroThreshold * settings.restGyroThreshold
    private val accThreshold2 = settings.restAccThreshold * settings.restAccThreshold
    private val minTime = settings.restMinTime

    private var started = false
    private var gx = 0.0
    private var gy = 0.0
    private var gz = 0.0
    private var ax = 0.0
    private var ay = 0.0
    private var az = 0.0
    /** Time the rest conditions have held, s. */
    var restTime = 0.0
        private set

    /** True once the rest conditions have held for restMinTime. */
    var atRest = false
        private set

    /**
     * One gyroscope step of [dt] s with the gyroscope reading and, when [accValid], the paired
     * accelerometer reading. Without an accelerometer the sensor is not considered at rest.
     */
    fun update(dt: Double, wx: Double, wy: Double, wz: Double, accValid: Boolean, sx: Double, sy: Double, sz: Double): Boolean {
        if (!accValid) {
            restTime = 0.0
            atRest = false
            return false
        }
        if (!started) {
            gx = wx; gy = wy; gz = wz
            ax = sx; ay = sy; az = sz
            started = true
        } else {
            val k = minOf(1.0, dt * (1.0 / LOW_PASS_TIME)) // first-order low-pass, time constant LOW_PASS_TIME
            gx += k * (wx - gx); gy += k * (wy - gy); gz += k * (wz - gz)
            ax += k * (sx - ax); ay += k * (sy - ay); az += k * (sz - az)
        }
        val dgx = wx - gx
        val dgy = wy - gy
        val dgz = wz - gz
        val dax = sx - ax
        val day = sy - ay
        val daz = sz - az
        val still = dgx * dgx + dgy * dgy + dgz * dgz < gyroThreshold2 &&
            gx * gx + gy * gy + gz * gz < gyroThreshold2 &&
            dax * dax + day * day + daz * daz < accThreshold2
        restTime = if (still) restTime + dt else 0.0
        atRest = still && restTime >= minTime
        return atRest
    }

    /** For a run backward in time (gyroscope readings negated): the gyroscope low-pass is negated too. */
    fun reverse() {
        gx = -gx; gy = -gy; gz = -gz
    }

    override fun reset() {
        started = false
        gx = 0.0; gy = 0.0; gz = 0.0
        ax = 0.0; ay = 0.0; az = 0.0
        restTime = 0.0
        atRest = false
    }

    /** The low-passed gyroscope and accelerometer, the time at rest and the verdict. */
    data class State(
        val started: Boolean, val gx: Double, val gy: Double, val gz: Double,
        val ax: Double, val ay: Double, val az: Double, val restTime: Double, val atRest: Boolean,
    )

    override fun state() = State(started, gx, gy, gz, ax, ay, az, restTime, atRest)

    override fun restore(state: State) {
        started = state.started
        gx = state.gx; gy = state.gy; gz = state.gz
        ax = state.ax; ay = state.ay; az = state.az
        restTime = state.restTime
        atRest = state.atRest
    }

    companion object {
        /** Time constant of the low-pass references, s. */
        const val LOW_PASS_TIME = 0.5
    }
}
