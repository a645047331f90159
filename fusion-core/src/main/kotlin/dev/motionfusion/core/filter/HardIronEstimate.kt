/*
 * The magnetometer's hard-iron offset, estimated from the recording itself (beyond the report;
 * hardIronThreshold > 0), and taken off every reading before the filter sees it.
 *
 * A magnetometer reads m = h + b: the field h plus an offset b fixed to the device (magnetised parts, a case,
 * other devices on the same mount, an operating system's calibration that is off). While the phone turns at
 * ω (device frame), a field fixed in the world turns the other way in the device frame, dh/dt = −ω × h, so
 *
 *     dm/dt + ω × m = ω × b,
 *
 * linear in b, with the gyroscope's bias-corrected rate and nothing else: no orientation estimate, no
 * reference field. Over windows of WINDOW seconds, y = m(end) − m(start) + ∫ ω × m dt = Ω × b with
 * Ω = ∫ ω dt; the windows' normal equations (Σ SᵀS + λI) b = Σ Sᵀy, S = [Ω]×, are summed (older windows
 * forgotten over hardIronTime) and solved as each window closes. A window that departs from the estimate so
 * far by more than HUBER weighs HUBER over its departure (a magnet passing by, a field that changes as the
 * phone is carried, the gyroscope's scale error). Only the components of b across the axes the phone turned
 * about are seen (λ keeps the others near 0); a phone carried upright and turned about the vertical sees the
 * two across it, which are the ones heading needs.
 *
 * What is taken off, from MIN_WINDOWS windows on: the estimate shrunk towards 0 by hardIronThreshold (its
 * length less the threshold, nothing if shorter). A calibrated magnetometer's estimate mostly stays within
 * the threshold and little changes; a magnet fixed to the phone, or a calibration off by several µT (ADVIO's
 * iPhone on its rig: 2–11 µT), is taken off. A reading beyond the earth's field stays as read ([takesOff]).
 *
 * Units: µT, rad/s, s. Allocation-free. Time reversed (the offline passes) the same equation holds with the
 * rates negated, so the estimate carries on through every pass.
 */
package dev.motionfusion.core.filter

import kotlin.math.exp
import kotlin.math.sqrt

internal class HardIronEstimate(settings: FilterSettings) : Stage<HardIronEstimate.State> {
    private val threshold = requireNotNull(settings.hardIronThreshold) { "hard-iron estimate is off" }
    private val forget = settings.hardIronTime?.let { exp(-WINDOW / it) } ?: 1.0

    /** The offset taken off the readings now, µT. */
    var x = 0.0
        private set
    var y = 0.0
        private set
    var z = 0.0
        private set

    // The estimate over the whole recording (forgotten over hardIronTime) and over the last RECENT_TIME.
    private val all = Sums()
    private val recent = Sums()

    // The windows' squared departures (µT²) from each estimate as it stood before them, low-passed over RECENT_TIME.
    private var departAll = 0.0
    private var departRecent = 0.0

    /** The latest valid reading as read, µT, and whether there is one. */
    var rawX = 0.0
        private set
    var rawY = 0.0
        private set
    var rawZ = 0.0
        private set
    private var held = false

    /** Whether the offset is taken off the latest reading ([takesOff]). */
    var applied = false
        private set

    // Windows closed (not forgotten): the estimate is taken off from MIN_WINDOWS on.
    private var closed = 0L

    // The open window: its start reading, ∫ω dt, ∫ω × m dt, its length (s); open = a start reading taken.
    private var open = false
    private var m0x = 0.0
    private var m0y = 0.0
    private var m0z = 0.0
    private var ox = 0.0
    private var oy = 0.0
    private var oz = 0.0
    private var cx = 0.0
    private var cy = 0.0
    private var cz = 0.0
    private var length = 0.0

    /** A magnetometer reading as read (µT, device frame); a non-finite one is no reading. */
    fun hold(mx: Double, my: Double, mz: Double) {
        held = mx.isFinite() && my.isFinite() && mz.isFinite()
        applied = held && takesOff(mx, my, mz)
        if (!held) return
        rawX = mx; rawY = my; rawZ = mz
    }

    /**
     * Whether the offset is taken off the reading [mx], [my], [mz]: from a reading within the earth's field only. One
     * beyond it (a raw magnetometer's, offset by hundreds of µT) stays as read, and out: taken off, an offset known
     * only across the axes the phone turned about would let it in with a heading that is not the field's, and
     * north would arrive in the middle of the recording.
     */
    fun takesOff(mx: Double, my: Double, mz: Double): Boolean = SensorRanges.isEarthField(mx, my, mz)

    /** The open window ends unused (a rotation the gyroscope did not measure, or time turned round). */
    fun dropWindow() {
        open = false
    }

    /**
     * The step [s] (its length and bias-corrected rate) with the held raw reading: the open window gathers it,
     * and closes (and the estimate is solved) once WINDOW long. Without a valid fresh reading ([Step.magFresh]
     * false) the open window is dropped. True when the offset was found changed (a magnet put on or taken off the
     * phone): the field the filter sees jumps, and what it learnt of it starts again. Its first estimate is not such a
     * jump: the heading's fast convergence started again then costs BROAD 2.28° → 3.50° and Tyrex 4.07° → 5.28°.
     */
    fun update(s: Step): Boolean {
        if (!held || !s.magFresh) {
            open = false
            return false
        }
        if (!open) {
            m0x = rawX; m0y = rawY; m0z = rawZ
            ox = 0.0; oy = 0.0; oz = 0.0; cx = 0.0; cy = 0.0; cz = 0.0; length = 0.0
            open = true
            return false
        }
        val dt = s.dt
        ox += s.wx * dt; oy += s.wy * dt; oz += s.wz * dt
        cx += (s.wy * rawZ - s.wz * rawY) * dt
        cy += (s.wz * rawX - s.wx * rawZ) * dt
        cz += (s.wx * rawY - s.wy * rawX) * dt
        length += dt
        return length >= WINDOW && closeWindow()
    }

    /** Closes the open window; true if the offset taken off changed at once (see [update]). */
    private fun closeWindow(): Boolean {
        val yx = rawX - m0x + cx
        val yy = rawY - m0y + cy
        val yz = rawZ - m0z + cz
        var w = 1.0
        if (closed >= MIN_WINDOWS) {
            // A window far from the estimate (a magnet passing by) weighs less in it.
            val e2 = all.departure2(ox, oy, oz, yx, yy, yz)
            if (e2 > HUBER * HUBER) w = HUBER / sqrt(e2)
            departAll += RECENT_RATE * (e2 - departAll)
            departRecent += RECENT_RATE * (recent.departure2(ox, oy, oz, yx, yy, yz) - departRecent)
        }
        all.add(w, forget, ox, oy, oz, yx, yy, yz)
        recent.add(1.0, RECENT_FORGET, ox, oy, oz, yx, yy, yz)
        closed++
        m0x = rawX; m0y = rawY; m0z = rawZ
        ox = 0.0; oy = 0.0; oz = 0.0; cx = 0.0; cy = 0.0; cz = 0.0; length = 0.0
        if (closed < MIN_WINDOWS) return false
        all.solve()
        recent.solve()
        // The offset changed (a magnet put on or taken off the phone): the windows depart from the whole recording's
        // estimate far more than from the recent one, which the whole recording's starts again from.
        val changed = departAll > CHANGED * departRecent + FLOOR
        if (changed) {
            all.take(recent)
            departAll = departRecent
        }
        val n = sqrt(all.bx * all.bx + all.by * all.by + all.bz * all.bz)
        val k = if (n > threshold) 1.0 - threshold / n else 0.0
        x = k * all.bx; y = k * all.by; z = k * all.bz
        return changed
    }

    override fun reset() = restore(NEW)

    /** The offset taken off, both estimates and their departures, the held reading and the open window. */
    data class State(
        val x: Double, val y: Double, val z: Double, val all: Sums.State, val recent: Sums.State,
        val departAll: Double, val departRecent: Double,
        val rawX: Double, val rawY: Double, val rawZ: Double, val held: Boolean, val applied: Boolean, val closed: Long,
        val open: Boolean, val m0x: Double, val m0y: Double, val m0z: Double,
        val ox: Double, val oy: Double, val oz: Double, val cx: Double, val cy: Double, val cz: Double, val length: Double,
    )

    override fun state() = State(
        x, y, z, all.state(), recent.state(), departAll, departRecent, rawX, rawY, rawZ, held, applied, closed, open, m0x, m0y, m0z,
        ox, oy, oz, cx, cy, cz, length,
    )

    override fun restore(state: State) {
        x = state.x; y = state.y; z = state.z
        all.restore(state.all); recent.restore(state.recent)
        departAll = state.departAll; departRecent = state.departRecent
        rawX = state.rawX; rawY = state.rawY; rawZ = state.rawZ; held = state.held; applied = state.applied; closed = state.closed
        open = state.open; m0x = state.m0x; m0y = state.m0y; m0z = state.m0z
        ox = state.ox; oy = state.oy; oz = state.oz; cx = state.cx; cy = state.cy; cz = state.cz; length = state.length
    }

    /**
     * The windows' normal equations, A b = r with A = Σ SᵀS (symmetric), r = Σ Sᵀy, S = [Ω]× (SᵀS = |Ω|² I − ΩΩᵀ,
     * Sᵀy = y × Ω), and their solution b.
     */
    class Sums {
        private var axx = 0.0
        private var ayy = 0.0
        private var azz = 0.0
        private var axy = 0.0
        private var axz = 0.0
        private var ayz = 0.0
        private var rx = 0.0
        private var ry = 0.0
        private var rz = 0.0

        var bx = 0.0
            private set
        var by = 0.0
            private set
        var bz = 0.0
            private set

        /** The older windows weighed by [forget], then the window Ω, y with weight [w]. */
        fun add(w: Double, forget: Double, ox: Double, oy: Double, oz: Double, yx: Double, yy: Double, yz: Double) {
            val o2 = ox * ox + oy * oy + oz * oz
            axx = forget * axx + w * (o2 - ox * ox)
            ayy = forget * ayy + w * (o2 - oy * oy)
            azz = forget * azz + w * (o2 - oz * oz)
            axy = forget * axy - w * ox * oy
            axz = forget * axz - w * ox * oz
            ayz = forget * ayz - w * oy * oz
            rx = forget * rx + w * (yy * oz - yz * oy)
            ry = forget * ry + w * (yz * ox - yx * oz)
            rz = forget * rz + w * (yx * oy - yy * ox)
        }

        /** |y − Ω × b|², µT²: how far the window Ω, y departs from the estimate b. */
        fun departure2(ox: Double, oy: Double, oz: Double, yx: Double, yy: Double, yz: Double): Double {
            val ex = yx - (oy * bz - oz * by)
            val ey = yy - (oz * bx - ox * bz)
            val ez = yz - (ox * by - oy * bx)
            return ex * ex + ey * ey + ez * ez
        }

        /** b = (A + λI)⁻¹ r, λ = RIDGE. */
        fun solve() {
            val a = axx + RIDGE
            val d = ayy + RIDGE
            val f = azz + RIDGE
            val b = axy
            val c = axz
            val e = ayz
            // The adjugate of the symmetric [[a b c] [b d e] [c e f]].
            val i00 = d * f - e * e
            val i01 = c * e - b * f
            val i02 = b * e - c * d
            val i11 = a * f - c * c
            val i12 = b * c - a * e
            val i22 = a * d - b * b
            val det = a * i00 + b * i01 + c * i02
            if (!(det > 0.0)) return
            bx = (i00 * rx + i01 * ry + i02 * rz) / det
            by = (i01 * rx + i11 * ry + i12 * rz) / det
            bz = (i02 * rx + i12 * ry + i22 * rz) / det
        }

        /** The sums and solution of [other] (allocates nothing). */
        fun take(o: Sums) {
            axx = o.axx; ayy = o.ayy; azz = o.azz; axy = o.axy; axz = o.axz; ayz = o.ayz
            rx = o.rx; ry = o.ry; rz = o.rz; bx = o.bx; by = o.by; bz = o.bz
        }

        data class State(
            val axx: Double, val ayy: Double, val azz: Double, val axy: Double, val axz: Double, val ayz: Double,
            val rx: Double, val ry: Double, val rz: Double, val bx: Double, val by: Double, val bz: Double,
        )

        fun state() = State(axx, ayy, azz, axy, axz, ayz, rx, ry, rz, bx, by, bz)

        fun restore(s: State) {
            axx = s.axx; ayy = s.ayy; azz = s.azz; axy = s.axy; axz = s.axz; ayz = s.ayz
            rx = s.rx; ry = s.ry; rz = s.rz; bx = s.bx; by = s.by; bz = s.bz
        }
    }

    private companion object {
        /** The window over which the field's change is compared with the gyroscope's, s. */
        const val WINDOW = 0.2

        /** Windows before the first estimate (10 s). */
        const val MIN_WINDOWS = 50L

        /** The ridge on the normal equations, rad²: the square of a turn of 0.1 rad. */
        const val RIDGE = 0.01

        /** A window that departs from the estimate by more than this, µT, weighs this much over its departure (Huber). */
        const val HUBER = 2.0

        /** The recent estimate's time, s: windows forgotten, and departures low-passed, over it. */
        const val RECENT_TIME = 15.0
        val RECENT_FORGET = exp(-WINDOW / RECENT_TIME)
        const val RECENT_RATE = WINDOW / RECENT_TIME

        /** The ratio of the departures from the two estimates at which the offset counts as changed. */
        const val CHANGED = 2.0

        /** µT², the departures' floor under which no change is seen. */
        const val FLOOR = 1.0

        val NEW = State(
            0.0, 0.0, 0.0, Sums().state(), Sums().state(), 0.0, 0.0, 0.0, 0.0, 0.0, false, false, 0L, false, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        )
    }
}
