/*
 * Magnetic trust (beyond the report; magTrustSpread > 0): how far the magnetometer can be trusted for
 * heading, judged continuously from the field itself, and the heading gain weighed by it.
 *
 * At one place the earth's field has a fixed magnitude and dip. Indoors, as the phone is carried through a
 * building, both wander (steel, escalators, a train); outdoors they stay. The check follows the field's
 * magnitude and the sine of its dip (against the estimated up) with means low-passed over magTrustTime,
 * and the low-passed square of their departure from those means, σ² = mean of (|m|/|m|_mean − 1)² +
 * (sin dip − mean)²: the field's wander. With r = min(1, magTrustSpread/σ), the heading gain is scaled by r
 * (full while the field wanders within the spread, then falling as 1/σ, a Kalman filter's steady state for
 * white errors) and the bias estimate in motion, which learns from the same heading error, by r³: a
 * building's field may still steer the heading a little, but it must not teach the gyroscope a bias, for
 * the gyroscope is what carries the heading through the building. Back to full as the wander decays. No
 * reference is learnt, so a disturbed start poisons nothing. Units: any field unit (only ratios enter), s.
 * Allocation-free.
 *
 * Off by default: the wander does not tell a building that misleads (ADVIO's walks) from one whose errors
 * average out as the phone turns in one room (Tyrex's, OxIOD's), and a gyroscope-only heading loses in the
 * latter; docs/ACCURACY.md gives the figures.
 */
package dev.motionfusion.core.filter

internal class MagneticTrust(settings: FilterSettings) : Check<MagneticTrust.State> {
    private val spread = requireNotNull(settings.magTrustSpread) { "magnetic trust is off" }
    private val spread2 = spread * spread
    private val rate = 1.0 / settings.magTrustTime

    private var normMean = 0.0
    private var dipMean = 0.0
    private var wander2 = 0.0

    /** The heading gain's factor of the last step, r, 0…1 (the bias estimate in motion's is r³). */
    var trust = 1.0
        private set

    /** Whether the trust holds the heading on the gyroscope: the heading gain below [HOLDS] of its own (FilterDiagnostics.magneticDisturbance). */
    val holds: Boolean get() = trust < HOLDS

    override fun check(s: Step) {
        if (!s.useMag) return
        val n2 = s.mx * s.mx + s.my * s.my + s.mz * s.mz
        if (!(n2 > 0.0)) return
        val inv = MadgwickSteps.invSqrt(n2)
        val norm = n2 * inv
        val sinDip = -(s.mx * s.ux + s.my * s.uy + s.mz * s.uz) * inv
        if (normMean == 0.0) {
            normMean = norm
            dipMean = sinDip
        }
        val a = minOf(1.0, s.dt * rate)
        normMean += a * (norm - normMean)
        dipMean += a * (sinDip - dipMean)
        val dn = norm / normMean - 1.0
        val dd = sinDip - dipMean
        wander2 += a * (dn * dn + dd * dd - wander2)
        trust = if (wander2 <= spread2) 1.0 else spread * MadgwickSteps.invSqrt(wander2)
        s.headingFactor *= trust
        s.biasFactor *= trust * trust
    }

    override fun reset() = restore(NEW)

    /** The field's low-passed magnitude and sin dip, its wander σ², and the last factor. */
    data class State(val normMean: Double, val dipMean: Double, val wander2: Double, val trust: Double)

    override fun state() = State(normMean, dipMean, wander2, trust)

    override fun restore(state: State) {
        normMean = state.normMean
        dipMean = state.dipMean
        wander2 = state.wander2
        trust = state.trust
    }

    private companion object {
        /** The factor below which the heading counts as held on the gyroscope. */
        const val HOLDS = 0.25
        val NEW = State(0.0, 0.0, 0.0, 1.0)
    }
}
