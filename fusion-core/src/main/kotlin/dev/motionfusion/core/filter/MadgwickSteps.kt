/*
 * The report's steps: S. O. H. Madgwick, "An efficient orientation filter for inertial and
 * inertial/magnetic sensor arrays", University of Bristol, 2010. Equation numbers are the report's.
 *
 * The estimate q̂ = [w, x, y, z] (Hamilton, the report's SEq_1..4) is the sensor's orientation in the
 * report's North-West-Up earth frame (v_earth = q̂ ⊗ v_sensor ⊗ q̂*); b = [0, bx, 0, bz] the reference
 * direction of flux (eq. 46). Readings in the device frame: gyroscope rad/s, accelerometer m/s²,
 * magnetometer µT (only directions enter). The gyroscope bias ω_b is GyroBiasEstimate's: the steps remove
 * it (eq. 49) and hand the drift term ζ to it (eqs. 47–48), which is its own writer.
 *
 * MARG step (eqs. 25–26, 29–30, 34, 44, 47–49, 12, 42–43, 45–46), IMU step (eqs. 25–26, 34, 44, 12,
 * 42–43), gyroscope integration (eq. 12), and the heading step apart from inclination (beyond the
 * report; headingGain > 0). Allocation-free.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.unitQuaternionUp
import kotlin.math.sqrt

internal class MadgwickSteps(private val bias: GyroBiasEstimate) : Stage<MadgwickSteps.State> {
    // Estimate q̂ (NWU), the report's SEq_1..4.
    var q1 = 1.0
        private set
    var q2 = 0.0
        private set
    var q3 = 0.0
        private set
    var q4 = 0.0
        private set

    // Reference direction of flux in the earth frame, b = [0, bx, 0, bz] (eq. 46); the report starts at [0, 1, 0, 0].
    private var bx = 1.0
    private var bz = 0.0

    /** Steps whose result was not finite (absurd readings), not applied (counted as FilterDiagnostics.skippedNonFinite). */
    var dropped = 0L
        private set

    // Estimated up in the sensor frame, q̂* ⊗ [0, 0, 0, 1] ⊗ q̂ (the terms of eq. 25).
    fun upX() = unitQuaternionUp(q1, q2, q3, q4) { x, _, _ -> x }
    fun upY() = unitQuaternionUp(q1, q2, q3, q4) { _, y, _ -> y }
    fun upZ() = unitQuaternionUp(q1, q2, q3, q4) { _, _, z -> z }

    /** The start from one reading (Initialisation.FIRST_SAMPLE): inclination from [s]'s accelerometer, heading from its magnetometer if [Step.magOk]. */
    fun startFrom(s: Step) {
        val q = InitialOrientation.nwu(s.ax, s.ay, s.az, s.magOk, s.mx, s.my, s.mz)
        q1 = q.w; q2 = q.x; q3 = q.y; q4 = q.z
        if (s.magOk) {
            val n = invSqrt(s.mx * s.mx + s.my * s.my + s.mz * s.mz)
            updateFluxReference(q1, q2, q3, q4, s.mx * n, s.my * n, s.mz * n, 1.0)
        }
    }

    /** Takes [w], [x], [y], [z] (NWU, unit) as the estimate, b kept. */
    fun take(w: Double, x: Double, y: Double, z: Double) {
        q1 = w; q2 = x; q3 = y; q4 = z
    }

    /**
     * The report's MARG update of [dt] s with gain [beta] on the reading of [s] ([Step.gx]…, the magnetometer's):
     * the accelerometer part from ([ax], [ay], [az]) (the reading the step uses) when [withAcc]. Without it (a
     * rejected accelerometer) the accelerometer's rows of f are left out: with b taken from the estimate (eq.
     * 46) the remaining gradient corrects heading only.
     */
    fun marg(s: Step, beta: Double, withAcc: Boolean, ax: Double, ay: Double, az: Double) {
        var f1 = 0.0
        var f2 = 0.0
        var f3 = 0.0
        if (withAcc) {
            val n = invSqrt(ax * ax + ay * ay + az * az)
            // Objective function, accelerometer part (eq. 25).
            f1 = 2.0 * (q2 * q4 - q1 * q3) - ax * n
            f2 = 2.0 * (q1 * q2 + q3 * q4) - ay * n
            f3 = 2.0 * (0.5 - q2 * q2 - q3 * q3) - az * n
        }
        val n = invSqrt(s.mx * s.mx + s.my * s.my + s.mz * s.mz)
        val m1 = s.mx * n
        val m2 = s.my * n
        val m3 = s.mz * n
        val twoBx = 2.0 * bx
        val twoBz = 2.0 * bz
        // Objective function, magnetometer part (eq. 29).
        val f4 = twoBx * (0.5 - q3 * q3 - q4 * q4) + twoBz * (q2 * q4 - q1 * q3) - m1
        val f5 = twoBx * (q2 * q3 - q1 * q4) + twoBz * (q1 * q2 + q3 * q4) - m2
        val f6 = twoBx * (q1 * q3 + q2 * q4) + twoBz * (0.5 - q2 * q2 - q3 * q3) - m3
        // Gradient ∇f = Jᵀ f with the Jacobians of eqs. 26 and 30 (eq. 34).
        val d1 = -2.0 * q3 * f1 + 2.0 * q2 * f2 -
            twoBz * q3 * f4 + (-twoBx * q4 + twoBz * q2) * f5 + twoBx * q3 * f6
        val d2 = 2.0 * q4 * f1 + 2.0 * q1 * f2 - 4.0 * q2 * f3 +
            twoBz * q4 * f4 + (twoBx * q3 + twoBz * q1) * f5 + (twoBx * q4 - 2.0 * twoBz * q2) * f6
        val d3 = -2.0 * q1 * f1 + 2.0 * q4 * f2 - 4.0 * q3 * f3 +
            (-2.0 * twoBx * q3 - twoBz * q1) * f4 + (twoBx * q2 + twoBz * q4) * f5 + (twoBx * q1 - 2.0 * twoBz * q3) * f6
        val d4 = 2.0 * q2 * f1 + 2.0 * q3 * f2 +
            (-2.0 * twoBx * q4 + twoBz * q2) * f4 + (-twoBx * q1 + twoBz * q3) * f5 + twoBx * q2 * f6
        correct(s.dt, s.gx, s.gy, s.gz, beta, d1, d2, d3, d4, true, m1, m2, m3)
    }

    /** The report's IMU update with the accelerometer reading ([ax], [ay], [az]); the report has no ζ here. */
    fun imu(s: Step, beta: Double, ax: Double, ay: Double, az: Double) {
        val n = invSqrt(ax * ax + ay * ay + az * az)
        val f1 = 2.0 * (q2 * q4 - q1 * q3) - ax * n
        val f2 = 2.0 * (q1 * q2 + q3 * q4) - ay * n
        val f3 = 2.0 * (0.5 - q2 * q2 - q3 * q3) - az * n
        correct(
            s.dt, s.gx, s.gy, s.gz, beta,
            -2.0 * q3 * f1 + 2.0 * q2 * f2,
            2.0 * q4 * f1 + 2.0 * q1 * f2 - 4.0 * q2 * f3,
            -2.0 * q1 * f1 + 2.0 * q4 * f2 - 4.0 * q3 * f3,
            2.0 * q2 * f1 + 2.0 * q3 * f2,
            false, 0.0, 0.0, 0.0,
        )
    }

    /** Gyroscope integration only (no usable accelerometer): eq. 12 with the bias removed. */
    fun gyro(s: Step, beta: Double) {
        correct(s.dt, s.gx, s.gy, s.gz, beta, 0.0, 0.0, 0.0, 0.0, false, 0.0, 0.0, 0.0)
    }

    /**
     * Heading correction apart from inclination (beyond the report; headingGain > 0): the measured
     * field in the earth frame, h = q̂ ⊗ m ⊗ q̂*, should point north (+x of NWU). The estimate is
     * turned about the earth's vertical towards that, by the fraction [k] of the heading error δ
     * (sin δ for |δ| < 90°, a quarter turn beyond), so inclination is left as the accelerometer made it.
     * Returns sin δ (0 for a field along the vertical).
     */
    fun heading(k: Double, mx: Double, my: Double, mz: Double): Double {
        val hx = earthX(q1, q2, q3, q4, mx, my, mz)
        val hy = earthY(q1, q2, q3, q4, mx, my, mz)
        val hn2 = hx * hx + hy * hy
        if (!(hn2 > 0.0)) return 0.0
        val sinDelta = if (hx > 0.0) hy * invSqrt(hn2) else if (hy >= 0.0) 1.0 else -1.0
        // q̂ ← [cos(a/2), 0, 0, sin(a/2)] ⊗ q̂ with a = −k·sin δ (small: cos ≈ 1, then normalised).
        val s = -0.5 * minOf(k, 1.0) * sinDelta
        val n1 = q1 - s * q4
        val n2 = q2 - s * q3
        val n3 = q3 + s * q2
        val n4 = q4 + s * q1
        val inv = invSqrt(n1 * n1 + n2 * n2 + n3 * n3 + n4 * n4)
        q1 = n1 * inv; q2 = n2 * inv; q3 = n3 * inv; q4 = n4 * inv
        return sinDelta
    }

    /**
     * Normalises the gradient (d1..d4) (eq. 44), has the bias take its drift term (eqs. 47–48; in the MARG
     * step, [flux]), removes the bias (eq. 49) and integrates with gain [beta] (eqs. 12, 42–43); with [flux],
     * updates b from the normalised magnetometer reading (m1, m2, m3) (eqs. 45–46). A zero gradient (exact
     * agreement) contributes no correction. A step whose result is not finite is dropped.
     */
    private fun correct(
        dt: Double, gx: Double, gy: Double, gz: Double, beta: Double,
        d1: Double, d2: Double, d3: Double, d4: Double,
        flux: Boolean, m1: Double, m2: Double, m3: Double,
    ) {
        // The gyroscope term with the previous bias does not depend on the gradient: computed first,
        // it overlaps with the gradient's normalisation.
        val h = 0.5 * dt
        val wx = gx - bias.x // (eq. 49)
        val wy = gy - bias.y
        val wz = gz - bias.z
        val p1 = q1 + h * (-q2 * wx - q3 * wy - q4 * wz)
        val p2 = q2 + h * (q1 * wx + q3 * wz - q4 * wy)
        val p3 = q3 + h * (q1 * wy - q2 * wz + q4 * wx)
        val p4 = q4 + h * (q1 * wz + q2 * wy - q3 * wx)
        val dn2 = d1 * d1 + d2 * d2 + d3 * d3 + d4 * d4
        val s = if (dn2 > 0.0) invSqrt(dn2) else 0.0
        val e1 = d1 * s
        val e2 = d2 * s
        val e3 = d3 * s
        val e4 = d4 * s
        // q̂ += (½ q̂ ⊗ [0, ω − ω_b] − β q̇_ε) Δt (eqs. 12, 42–43).
        var c1 = beta * dt
        var c2 = 0.0
        if (flux && bias.drifts) {
            // ω_ε = 2 q̂* ⊗ q̇_ε (eq. 47); ω_b += ζ ω_ε Δt (eq. 48). The bias change Δω_b = ζΔt ω_ε enters
            // the rate as ½ q̂ ⊗ [0, −Δω_b] = −ζΔt (q̇_ε − (q̂·q̇_ε) q̂), because q̂ ⊗ (q̂* ⊗ q̇_ε) = q̇_ε.
            val k = bias.drift(dt, q1, q2, q3, q4, e1, e2, e3, e4)
            val kdt = k * dt
            c1 += kdt
            c2 = kdt * (q1 * e1 + q2 * e2 + q3 * e3 + q4 * e4)
        }
        val n1 = p1 - c1 * e1 + c2 * q1
        val n2 = p2 - c1 * e2 + c2 * q2
        val n3 = p3 - c1 * e3 + c2 * q3
        val n4 = p4 - c1 * e4 + c2 * q4
        val n = n1 * n1 + n2 * n2 + n3 * n3 + n4 * n4
        val inv = invSqrt(n)
        if (!(inv > 0.0 && inv.isFinite())) {
            dropped++
            return
        }
        q1 = n1 * inv; q2 = n2 * inv; q3 = n3 * inv; q4 = n4 * inv
        // b from the new estimate: computed from the unnormalised n, scaled by 1/|n|², so that it
        // does not wait for the normalisation.
        if (flux) updateFluxReference(n1, n2, n3, n4, m1, m2, m3, 1.0 / n)
    }

    /**
     * Magnetic distortion compensation (eqs. 45–46): h = q̂ ⊗ [0, m] ⊗ q̂*, b = [0, √(hx² + hy²), 0, hz],
     * with q̂ = p/|p| given as p = (p1..p4) and [s] = 1/|p|² (h is quadratic in q̂).
     */
    private fun updateFluxReference(p1: Double, p2: Double, p3: Double, p4: Double, m1: Double, m2: Double, m3: Double, s: Double) {
        val hx = earthX(p1, p2, p3, p4, m1, m2, m3)
        val hy = earthY(p1, p2, p3, p4, m1, m2, m3)
        val hz = m3 * (p1 * p1 - p2 * p2 - p3 * p3 + p4 * p4) + 2.0 * (m1 * (p2 * p4 - p1 * p3) + m2 * (p3 * p4 + p1 * p2))
        bx = sqrt(hx * hx + hy * hy) * s
        bz = hz * s
    }

    // x and y of p ⊗ [0, m] ⊗ p* (|p|² times the rotated vector): the horizontal part of m in the earth frame.
    private fun earthX(p1: Double, p2: Double, p3: Double, p4: Double, m1: Double, m2: Double, m3: Double) =
        m1 * (p1 * p1 + p2 * p2 - p3 * p3 - p4 * p4) + 2.0 * (m2 * (p2 * p3 - p1 * p4) + m3 * (p2 * p4 + p1 * p3))

    private fun earthY(p1: Double, p2: Double, p3: Double, p4: Double, m1: Double, m2: Double, m3: Double) =
        m2 * (p1 * p1 - p2 * p2 + p3 * p3 - p4 * p4) + 2.0 * (m1 * (p2 * p3 + p1 * p4) + m3 * (p3 * p4 - p1 * p2))

    /** q̂ (NWU), b and the count of dropped steps. */
    data class State(val q1: Double, val q2: Double, val q3: Double, val q4: Double, val bx: Double, val bz: Double, val dropped: Long)

    override fun state() = State(q1, q2, q3, q4, bx, bz, dropped)

    override fun restore(state: State) {
        q1 = state.q1; q2 = state.q2; q3 = state.q3; q4 = state.q4
        bx = state.bx; bz = state.bz
        dropped = state.dropped
    }

    override fun reset() = restore(NEW)

    companion object {
        private val NEW = State(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0L)

        /** 1/√x as √x · (1/x): the square root and the division run in parallel (shorter latency than 1/√x). */
        fun invSqrt(x: Double): Double = sqrt(x) * (1.0 / x)
    }
}
