/*
 * The accelerometer low-passed in a quasi-inertial frame (beyond the report; accLowPassTime > 0).
 *
 * The held value, a vector fixed in a frame that turns with the bias-corrected gyroscope (w_x, w_y, w_z),
 * is first turned with it, v ← R(−ωΔt) v (Rodrigues' formula to fourth order in |ω|Δt), then moved
 * towards the reading with the time constant accLowPassTime. Gravity is fixed in that frame and passes
 * unchanged; linear acceleration, whose integral is a bounded velocity, averages out. A reading the
 * accelerometer rejection leaves out still enters the low-pass (the steps then do without it). Without a
 * fresh reading the low-pass stops; the next reading starts it again, and until accLowPassTime has passed
 * since then the value is the mean of the readings since (turned alike), so a start in motion is not held
 * for long. Sensor-frame coordinates, m/s², rad/s, s. Allocation-free.
 */
package dev.motionfusion.core.filter

internal class AccelerometerLowPass(settings: FilterSettings) : Stage<AccelerometerLowPass.State> {
    private val time = settings.accLowPassTime ?: 0.0

    /** False with accLowPassTime off: the steps use the reading itself. */
    val enabled = settings.accLowPassTime != null

    /** The low-passed reading (sensor frame, m/s²): what the correction steps use when [enabled]. */
    var x = 0.0
        private set
    var y = 0.0
        private set
    var z = 0.0
        private set

    // The next reading starts the low-pass again.
    private var fresh = true

    // Time since the low-pass started, s: until it reaches accLowPassTime the value is the mean since then.
    private var elapsed = 0.0

    /** The next reading starts the low-pass again (its frame went through a rotation the gyroscope missed). */
    fun restart() {
        fresh = true
    }

    /** One step of [dt] s with the bias-corrected rate [wx], [wy], [wz] and, when [withAcc], the reading [ax], [ay], [az]. */
    fun update(dt: Double, wx: Double, wy: Double, wz: Double, withAcc: Boolean, ax: Double, ay: Double, az: Double) {
        if (!withAcc) {
            fresh = true
            return
        }
        if (fresh) {
            x = ax; y = ay; z = az
            fresh = false
            elapsed = 0.0
            return
        }
        val rx = wx * dt
        val ry = wy * dt
        val rz = wz * dt
        val t2 = rx * rx + ry * ry + rz * rz
        val s1 = 1.0 - t2 * (1.0 / 6.0) // sin θ / θ
        val s2 = 0.5 - t2 * (1.0 / 24.0) // (1 − cos θ) / θ²
        // r × v and r × (r × v), turned by −θ: v' = v − s1 (r × v) + s2 r × (r × v).
        val cx = ry * z - rz * y
        val cy = rz * x - rx * z
        val cz = rx * y - ry * x
        val vx = x - s1 * cx + s2 * (ry * cz - rz * cy)
        val vy = y - s1 * cy + s2 * (rz * cx - rx * cz)
        val vz = z - s1 * cz + s2 * (rx * cy - ry * cx)
        val k = dt / (minOf(elapsed, time) + dt)
        elapsed += dt
        x = vx + k * (ax - vx)
        y = vy + k * (ay - vy)
        z = vz + k * (az - vz)
    }

    override fun reset() {
        x = 0.0; y = 0.0; z = 0.0
        fresh = true
        elapsed = 0.0
    }

    /** The low-passed reading, whether the next reading starts it again, and the time since it started. */
    data class State(val x: Double, val y: Double, val z: Double, val fresh: Boolean, val elapsed: Double)

    override fun state() = State(x, y, z, fresh, elapsed)

    override fun restore(state: State) {
        x = state.x; y = state.y; z = state.z
        fresh = state.fresh
        elapsed = state.elapsed
    }
}
