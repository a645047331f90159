/*
 * Rest detection for the gyroscope bias estimate (beyond the report).
 *
 * Inputs in the Android device frame, SI units (rad/s, m/s², s). The sensor is at rest when, for
 * at least restMinTime, the gyroscope stays within restGyroThreshold of its low-passed value, that
 * low-passed value (the bias the rest estimate takes) stays within restGyroThreshold of zero, and the
 * accelerometer stays within
 * restAccThreshold of its low-passed value, and, unless these have held for restImplausibleTime, the
 * low-passed gyroscope has stayed within restMaxRate of zero for restMinTime (a slow turn below
 * restGyroThreshold, as of a phone carried upright or an elevator ride, looks like a rest with its rate as bias). Allocation-free; state is primitive fields.
 */
package dev.motionfusion.core.filter

internal class RestDetector(settings: FilterSettings) : Stage<RestDetector.State> {
    private val gyroThreshold2 = settings.restGyroThreshold * settings.restGyroThreshold
    private val maxRate2 = settings.restMaxRate * settings.restMaxRate
    private val implausibleTime = maxOf(settings.restMinTime, settings.restImplausibleTime)
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

    /** Whether the last step declared the rest (the first of its steps at rest). */
    var declared = false
        private set

    /** Time the rest conditions have held with the low-passed gyroscope within restMaxRate, s. */
    var plausibleTime = 0.0
        private set

    // The gyroscope readings, each times its step (rad), since the rest conditions have held within restMaxRate
    // ([plausibleTime]).
    private var plausibleX = 0.0
    private var plausibleY = 0.0
    private var plausibleZ = 0.0

    /** Whether the rest conditions have held within restMaxRate for restMinTime (the rest is declared by them). */
    val plausible: Boolean get() = plausibleTime >= minTime

    /**
     * The rest's mean gyroscope reading, rad/s: over [plausibleTime] for a rest declared by it (a slow turn before
     * that stretch is no part of the bias); for one declared after restImplausibleTime, the low-passed rate (what it
     * was over the last [LOW_PASS_TIME]: a turn that stopped before then is no part of it).
     */
    val meanX: Double get() = if (plausible) plausibleX / plausibleTime else gx
    val meanY: Double get() = if (plausible) plausibleY / plausibleTime else gy
    val meanZ: Double get() = if (plausible) plausibleZ / plausibleTime else gz

    /** True once the rest conditions have held for restMinTime (restImplausibleTime for a mean rate beyond restMaxRate). */
    var atRest = false
        private set

    /**
     * One gyroscope step of [dt] s with the gyroscope reading and, when [accValid], the paired
     * accelerometer reading. Without an accelerometer the sensor is not considered at rest.
     */
    fun update(dt: Double, wx: Double, wy: Double, wz: Double, accValid: Boolean, sx: Double, sy: Double, sz: Double): Boolean {
        if (!accValid) {
            restTime = 0.0
            plausibleTime = 0.0
            plausibleX = 0.0; plausibleY = 0.0; plausibleZ = 0.0
            atRest = false
            declared = false
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
        // A mean rate beyond restMaxRate is more likely a slow turn than a bias: the rest conditions must then have
        // held for restImplausibleTime, else restMinTime within restMaxRate.
        if (still && gx * gx + gy * gy + gz * gz < maxRate2) {
            plausibleTime += dt
            plausibleX += wx * dt; plausibleY += wy * dt; plausibleZ += wz * dt
        } else {
            plausibleTime = 0.0
            plausibleX = 0.0; plausibleY = 0.0; plausibleZ = 0.0
        }
        val was = atRest
        atRest = still && (plausibleTime >= minTime || restTime >= implausibleTime)
        declared = atRest && !was
        return atRest
    }

    /** For a run backward in time (gyroscope readings negated): the gyroscope low-pass is negated too. */
    fun reverse() {
        gx = -gx; gy = -gy; gz = -gz
        plausibleX = -plausibleX; plausibleY = -plausibleY; plausibleZ = -plausibleZ
    }

    override fun reset() {
        started = false
        gx = 0.0; gy = 0.0; gz = 0.0
        ax = 0.0; ay = 0.0; az = 0.0
        restTime = 0.0
        atRest = false
        declared = false
        plausibleTime = 0.0
        plausibleX = 0.0; plausibleY = 0.0; plausibleZ = 0.0
    }

    /** The low-passed gyroscope and accelerometer, the time at rest, the verdict, the rest plausibility's time and the sum of its readings. */
    data class State(
        val started: Boolean, val gx: Double, val gy: Double, val gz: Double,
        val ax: Double, val ay: Double, val az: Double, val restTime: Double, val atRest: Boolean,
        val plausibleTime: Double, val plausibleX: Double, val plausibleY: Double, val plausibleZ: Double,
    )

    override fun state() = State(started, gx, gy, gz, ax, ay, az, restTime, atRest, plausibleTime, plausibleX, plausibleY, plausibleZ)

    override fun restore(state: State) {
        started = state.started
        gx = state.gx; gy = state.gy; gz = state.gz
        ax = state.ax; ay = state.ay; az = state.az
        restTime = state.restTime
        atRest = state.atRest
        declared = false
        plausibleTime = state.plausibleTime
        plausibleX = state.plausibleX; plausibleY = state.plausibleY; plausibleZ = state.plausibleZ
    }

    companion object {
        /** Time constant of the low-pass references, s. */
        const val LOW_PASS_TIME = 0.5
    }
}
