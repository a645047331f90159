/*
 * The gyroscope bias observed through the accelerometer (beyond the report; accBiasEstimation), the way of
 * VQF (Laidig & Seel 2023): a Kalman filter on the bias ω_b (rad/s, device frame) whose measurement is the
 * inclination correction. The unit runs an inclination estimate of its own, free of the magnetometer and of
 * the filter's gains: the gyroscope (bias removed) integrated into a quasi-inertial frame, the accelerometer
 * turned into that frame and low-passed (accBiasLowPassTime), and that low-passed gravity turned fully onto
 * the vertical every step. The rotation rate of that correction is what the horizontal part of the bias
 * (in the earth frame) left behind; as the phone turns, every axis of the device is horizontal at times,
 * so all three components become observable. Only a phone that keeps one axis vertical leaves that axis's
 * bias unobserved: its variance grows (accBiasForgettingTime) and the pseudo-measurement "vertical bias 0"
 * (accBiasVerticalFactor) holds it weakly.
 *
 * At rest (the rest detector of GyroBiasEstimate, whose mean then sets the bias) the Kalman filter's
 * covariance shrinks as for a measurement of the bias itself, so a fresh rest estimate is not moved by the
 * motion measurements that follow until its variance has grown again. The correction and the bias are
 * clipped to ±motionBiasLimit per axis. Allocation-free; its state is [State] (primitive doubles, for a
 * snapshot), [reset] starts it again.
 */
package dev.motionfusion.core.filter

import kotlin.math.sqrt

internal class AccelerometerBiasEstimate(settings: FilterSettings) {
    /** Whether the unit acts (accBiasEstimation). */
    val enabled = settings.accBiasEstimation

    private val lowPassTime = settings.accBiasLowPassTime
    private val clip = settings.motionBiasLimit

    // Variances in (rad/s)²: initial, growth per second (to (0.1°/s)² over accBiasForgettingTime), motion and rest
    // measurement noises (VQF's construction: for a measurement of variance p every Δt, W = p²/(vΔt) + p).
    private val p0 = sq(SIGMA_INIT)
    private val vRate = sq(SIGMA_GROWTH) / settings.accBiasForgettingTime
    private val pMotion = sq(settings.accBiasSigmaMotion)
    private val pRest = sq(SIGMA_REST)
    private val verticalFactor = settings.accBiasVerticalFactor

    /** The unit's state: its own inclination estimate, the low-pass states and the Kalman covariance. */
    internal data class State(
        var started: Boolean = false,
        // Gyroscope-integrated orientation (quasi-inertial frame ← device) and the inclination correction.
        var g0: Double = 1.0, var g1: Double = 0.0, var g2: Double = 0.0, var g3: Double = 0.0,
        var c0: Double = 1.0, var c1: Double = 0.0, var c2: Double = 0.0, var c3: Double = 0.0,
        // Low-passed accelerometer in the quasi-inertial frame.
        var ax: Double = 0.0, var ay: Double = 0.0, var az: Double = 0.0,
        // Low-passed rotation matrix (earth ← device) and the low-passed horizontal part of R·ω_b.
        val r: DoubleArray = DoubleArray(9),
        var bx: Double = 0.0, var by: Double = 0.0,
        // Covariance of ω_b (symmetric 3×3, row-major).
        val p: DoubleArray = DoubleArray(9),
    )

    val state = State()

    // Scratch for the Kalman update.
    private val h = DoubleArray(9)
    private val s = DoubleArray(9)
    private val k = DoubleArray(9)
    private val e = DoubleArray(3)
    private val t = DoubleArray(9)

    init {
        reset()
    }

    /**
     * One step of [dt] s: [gx], [gy], [gz] the gyroscope reading, [bias] the current estimate ω_b (updated in place),
     * [accOk] with the accelerometer reading [ax], [ay], [az]; [atRest] when the rest estimate has just set the bias.
     */
    fun update(dt: Double, gx: Double, gy: Double, gz: Double, accOk: Boolean, ax: Double, ay: Double, az: Double, atRest: Boolean, bias: DoubleArray) {
        val st = state
        // Strapdown with the bias removed: g ← g ⊗ exp(½ (ω − ω_b) Δt).
        integrate(st, (gx - bias[0]) * dt, (gy - bias[1]) * dt, (gz - bias[2]) * dt)
        grow(dt)
        if (!accOk) return
        // The accelerometer in the quasi-inertial frame, low-passed.
        val ix = rotX(st.g0, st.g1, st.g2, st.g3, ax, ay, az)
        val iy = rotY(st.g0, st.g1, st.g2, st.g3, ax, ay, az)
        val iz = rotZ(st.g0, st.g1, st.g2, st.g3, ax, ay, az)
        val kl = if (!st.started) 1.0 else minOf(1.0, dt / lowPassTime)
        st.ax += kl * (ix - st.ax); st.ay += kl * (iy - st.ay); st.az += kl * (iz - st.az)
        // Into the earth frame with the inclination correction, normalised.
        var ex = rotX(st.c0, st.c1, st.c2, st.c3, st.ax, st.ay, st.az)
        var ey = rotY(st.c0, st.c1, st.c2, st.c3, st.ax, st.ay, st.az)
        var ez = rotZ(st.c0, st.c1, st.c2, st.c3, st.ax, st.ay, st.az)
        val n = sqrt(ex * ex + ey * ey + ez * ez)
        if (!(n > 0.0)) return
        ex /= n; ey /= n; ez /= n
        // Turn it fully onto the vertical: c ← [w, ½ey/w, −½ex/w, 0] ⊗ c.
        val w = sqrt((ez + 1.0) * 0.5)
        if (w > 1e-6) {
            val qx = 0.5 * ey / w
            val qy = -0.5 * ex / w
            val n0 = w * st.c0 - qx * st.c1 - qy * st.c2
            val n1 = w * st.c1 + qx * st.c0 + qy * st.c3
            val n2 = w * st.c2 - qx * st.c3 + qy * st.c0
            val n3 = w * st.c3 + qx * st.c2 - qy * st.c1
            val m = 1.0 / sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
            st.c0 = n0 * m; st.c1 = n1 * m; st.c2 = n2 * m; st.c3 = n3 * m
        }
        // R of the corrected orientation c ⊗ g (earth ← device), its low-pass and that of the horizontal part of R·ω_b.
        val q0 = st.c0 * st.g0 - st.c1 * st.g1 - st.c2 * st.g2 - st.c3 * st.g3
        val q1 = st.c0 * st.g1 + st.c1 * st.g0 + st.c2 * st.g3 - st.c3 * st.g2
        val q2 = st.c0 * st.g2 - st.c1 * st.g3 + st.c2 * st.g0 + st.c3 * st.g1
        val q3 = st.c0 * st.g3 + st.c1 * st.g2 - st.c2 * st.g1 + st.c3 * st.g0
        matrix(q0, q1, q2, q3, t)
        val rbx = t[0] * bias[0] + t[1] * bias[1] + t[2] * bias[2]
        val rby = t[3] * bias[0] + t[4] * bias[1] + t[5] * bias[2]
        val r = st.r
        if (!st.started) {
            t.copyInto(r)
            st.bx = rbx; st.by = rby
            st.started = true
            return
        }
        for (i in 0 until 9) r[i] += kl * (t[i] - r[i])
        st.bx += kl * (rbx - st.bx); st.by += kl * (rby - st.by)
        if (atRest) {
            // The rest mean is a measurement of the bias itself: only the covariance changes here.
            for (i in 0 until 9) h[i] = if (i % 4 == 0) 1.0 else 0.0
            e[0] = 0.0; e[1] = 0.0; e[2] = 0.0
            val wr = pRest * pRest / (vRate * dt) + pRest
            kalman(wr, wr, wr, bias)
            return
        }
        e[0] = -ey / dt + st.bx - (r[0] * bias[0] + r[1] * bias[1] + r[2] * bias[2])
        e[1] = ex / dt + st.by - (r[3] * bias[0] + r[4] * bias[1] + r[5] * bias[2])
        e[2] = -(r[6] * bias[0] + r[7] * bias[1] + r[8] * bias[2])
        r.copyInto(h)
        val wm = pMotion * pMotion / (vRate * dt) + pMotion
        kalman(wm, wm, wm / maxOf(verticalFactor, 1e-10), bias)
    }

    /** Covariance growth over [dt] s, each variance up to its initial value. */
    private fun grow(dt: Double) {
        val p = state.p
        val v = vRate * dt
        if (p[0] < p0) p[0] += v
        if (p[4] < p0) p[4] += v
        if (p[8] < p0) p[8] += v
    }

    /** K = P Hᵀ (W + H P Hᵀ)⁻¹; ω_b += K e (e clipped); P −= K H P; ω_b clipped. */
    private fun kalman(w0: Double, w1: Double, w2: Double, bias: DoubleArray) {
        val p = state.p
        for (i in 0 until 3) e[i] = e[i].coerceIn(-clip, clip)
        // t = P Hᵀ
        for (i in 0 until 3) for (j in 0 until 3) t[3 * i + j] = p[3 * i] * h[3 * j] + p[3 * i + 1] * h[3 * j + 1] + p[3 * i + 2] * h[3 * j + 2]
        // s = H t + W
        for (i in 0 until 3) for (j in 0 until 3) s[3 * i + j] = h[3 * i] * t[j] + h[3 * i + 1] * t[3 + j] + h[3 * i + 2] * t[6 + j]
        s[0] += w0; s[4] += w1; s[8] += w2
        // s⁻¹ (adjugate over the determinant), into k temporarily.
        val det = s[0] * (s[4] * s[8] - s[5] * s[7]) - s[1] * (s[3] * s[8] - s[5] * s[6]) + s[2] * (s[3] * s[7] - s[4] * s[6])
        if (!(det != 0.0 && det.isFinite())) return
        val id = 1.0 / det
        k[0] = (s[4] * s[8] - s[5] * s[7]) * id; k[1] = (s[2] * s[7] - s[1] * s[8]) * id; k[2] = (s[1] * s[5] - s[2] * s[4]) * id
        k[3] = (s[5] * s[6] - s[3] * s[8]) * id; k[4] = (s[0] * s[8] - s[2] * s[6]) * id; k[5] = (s[2] * s[3] - s[0] * s[5]) * id
        k[6] = (s[3] * s[7] - s[4] * s[6]) * id; k[7] = (s[1] * s[6] - s[0] * s[7]) * id; k[8] = (s[0] * s[4] - s[1] * s[3]) * id
        k.copyInto(s)
        // K = t s⁻¹
        for (i in 0 until 3) for (j in 0 until 3) k[3 * i + j] = t[3 * i] * s[j] + t[3 * i + 1] * s[3 + j] + t[3 * i + 2] * s[6 + j]
        for (i in 0 until 3) bias[i] = (bias[i] + k[3 * i] * e[0] + k[3 * i + 1] * e[1] + k[3 * i + 2] * e[2]).coerceIn(-clip, clip)
        // P −= K (H P): s = H P, then P −= K s.
        for (i in 0 until 3) for (j in 0 until 3) s[3 * i + j] = h[3 * i] * p[j] + h[3 * i + 1] * p[3 + j] + h[3 * i + 2] * p[6 + j]
        for (i in 0 until 3) for (j in 0 until 3) t[3 * i + j] = p[3 * i + j] - (k[3 * i] * s[j] + k[3 * i + 1] * s[3 + j] + k[3 * i + 2] * s[6 + j])
        // Kept symmetric.
        for (i in 0 until 3) for (j in 0 until 3) p[3 * i + j] = 0.5 * (t[3 * i + j] + t[3 * j + i])
    }

    private fun integrate(st: State, rx: Double, ry: Double, rz: Double) {
        val a2 = rx * rx + ry * ry + rz * rz
        val a = sqrt(a2)
        val cw: Double
        val sf: Double
        if (a < 1e-8) {
            cw = 1.0 - a2 / 8.0; sf = 0.5 - a2 / 48.0
        } else {
            cw = kotlin.math.cos(0.5 * a); sf = kotlin.math.sin(0.5 * a) / a
        }
        val dx = rx * sf
        val dy = ry * sf
        val dz = rz * sf
        val n0 = st.g0 * cw - st.g1 * dx - st.g2 * dy - st.g3 * dz
        val n1 = st.g0 * dx + st.g1 * cw + st.g2 * dz - st.g3 * dy
        val n2 = st.g0 * dy - st.g1 * dz + st.g2 * cw + st.g3 * dx
        val n3 = st.g0 * dz + st.g1 * dy - st.g2 * dx + st.g3 * cw
        val m = 1.0 / sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
        st.g0 = n0 * m; st.g1 = n1 * m; st.g2 = n2 * m; st.g3 = n3 * m
    }

    /** For a pass backward in time (gyroscope readings negated): the state stays (the bias is negated by its owner). */
    fun reverse() {
        val st = state
        // The gyroscope-integrated frame runs on with negated readings; nothing of it depends on the sign.
        st.bx = -st.bx; st.by = -st.by
    }

    fun reset() {
        val st = state
        st.started = false
        st.g0 = 1.0; st.g1 = 0.0; st.g2 = 0.0; st.g3 = 0.0
        st.c0 = 1.0; st.c1 = 0.0; st.c2 = 0.0; st.c3 = 0.0
        st.ax = 0.0; st.ay = 0.0; st.az = 0.0
        st.r.fill(0.0)
        st.bx = 0.0; st.by = 0.0
        st.p.fill(0.0)
        st.p[0] = p0; st.p[4] = p0; st.p[8] = p0
    }

    fun writeState(d: DoubleArray, at: Int): Int {
        val st = state
        d[at] = if (st.started) 1.0 else 0.0
        d[at + 1] = st.g0; d[at + 2] = st.g1; d[at + 3] = st.g2; d[at + 4] = st.g3
        d[at + 5] = st.c0; d[at + 6] = st.c1; d[at + 7] = st.c2; d[at + 8] = st.c3
        d[at + 9] = st.ax; d[at + 10] = st.ay; d[at + 11] = st.az
        st.r.copyInto(d, at + 12)
        d[at + 21] = st.bx; d[at + 22] = st.by
        st.p.copyInto(d, at + 23)
        return at + STATE_SIZE
    }

    fun readState(d: DoubleArray, at: Int): Int {
        val st = state
        st.started = d[at] != 0.0
        st.g0 = d[at + 1]; st.g1 = d[at + 2]; st.g2 = d[at + 3]; st.g3 = d[at + 4]
        st.c0 = d[at + 5]; st.c1 = d[at + 6]; st.c2 = d[at + 7]; st.c3 = d[at + 8]
        st.ax = d[at + 9]; st.ay = d[at + 10]; st.az = d[at + 11]
        d.copyInto(st.r, 0, at + 12, at + 21)
        st.bx = d[at + 21]; st.by = d[at + 22]
        d.copyInto(st.p, 0, at + 23, at + 32)
        return at + STATE_SIZE
    }

    companion object {
        const val STATE_SIZE = 32
        private const val DEG = Math.PI / 180.0

        /** The bias's initial standard deviation (also its ceiling), its growth over accBiasForgettingTime, and a rest estimate's (VQF's values). */
        const val SIGMA_INIT = 0.5 * DEG
        const val SIGMA_GROWTH = 0.1 * DEG
        const val SIGMA_REST = 0.03 * DEG

        private fun sq(x: Double) = x * x

        // v rotated by the unit quaternion q: q ⊗ v ⊗ q*.
        private fun rotX(w: Double, x: Double, y: Double, z: Double, vx: Double, vy: Double, vz: Double) =
            (1 - 2 * (y * y + z * z)) * vx + 2 * (x * y - w * z) * vy + 2 * (x * z + w * y) * vz

        private fun rotY(w: Double, x: Double, y: Double, z: Double, vx: Double, vy: Double, vz: Double) =
            2 * (x * y + w * z) * vx + (1 - 2 * (x * x + z * z)) * vy + 2 * (y * z - w * x) * vz

        private fun rotZ(w: Double, x: Double, y: Double, z: Double, vx: Double, vy: Double, vz: Double) =
            2 * (x * z - w * y) * vx + 2 * (y * z + w * x) * vy + (1 - 2 * (x * x + y * y)) * vz

        private fun matrix(w: Double, x: Double, y: Double, z: Double, m: DoubleArray) {
            m[0] = 1 - 2 * (y * y + z * z); m[1] = 2 * (x * y - w * z); m[2] = 2 * (x * z + w * y)
            m[3] = 2 * (x * y + w * z); m[4] = 1 - 2 * (x * x + z * z); m[5] = 2 * (y * z - w * x)
            m[6] = 2 * (x * z - w * y); m[7] = 2 * (y * z + w * x); m[8] = 1 - 2 * (x * x + y * y)
        }
    }
}
