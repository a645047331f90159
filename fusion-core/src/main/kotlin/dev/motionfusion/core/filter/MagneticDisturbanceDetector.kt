/*
 * Magnetic disturbance detection (beyond the report).
 *
 * The earth's field has, at one place, a fixed magnitude and a fixed dip angle δ (its angle below
 * the horizontal). A field whose magnitude or dip departs from a learned reference is disturbed
 * (a magnet, steel, a motor) and the filter then leaves the magnetometer out, so the gyroscope holds
 * heading. The dip is measured against the filter's own up direction, not the raw accelerometer,
 * so linear acceleration does not look like a disturbance; a new reference is taken against the
 * raw accelerometer, so it does not depend on an estimate that may not have converged yet. Units: µT (any unit, consistently),
 * radians, seconds. Allocation-free and free of trigonometric calls per sample.
 *
 * Holding heading through a disturbance on a phone (magNewFieldMinGyro, magResumeTime): a steady new field
 * is learnt only from the time the phone turns (a field that is steady because nothing moves says nothing
 * about whether it is the environment's), and once the field is trusted again the heading gain comes back
 * as a ramp ([gainFactor]) instead of at once, so the heading the gyroscope carried is not pulled with a jump.
 *
 * A hold limited in time (magRejectionFactor, magFirstFieldTime, magUndisturbedTime; the counting of VQF,
 * Laidig & Seel 2023): the time rejected is a budget that fills while the field is disturbed and drains at
 * magRejectionFactor while it is not; with the budget spent the disturbed field is used at a reduced gain and
 * the reference is kept. The first reference is a field that stayed steady for magFirstFieldTime rather than
 * the first reading (until then the field is used), and a disturbance ends once the field has agreed with the
 * reference for magUndisturbedTime.
 */
package dev.motionfusion.core.filter

import kotlin.math.cos
import kotlin.math.sqrt

internal class MagneticDisturbanceDetector(settings: FilterSettings) : Check<MagneticDisturbanceDetector.State> {
    private val normTolerance = settings.magNormTolerance
    private val cosDipTolerance = cos(settings.magDipTolerance)
    private val maxRejectionTime = settings.magMaxRejectionTime
    private val referenceRate = 1.0 / settings.magReferenceTime
    // Each mechanism on or off once, here (null in FilterSettings); the steps read flags and plain numbers.
    private val learnsNewField = settings.magNewFieldTime != null
    private val newFieldTime = settings.magNewFieldTime ?: 0.0
    private val newFieldMinGyro2 = settings.magNewFieldMinGyro?.let { it * it } ?: 0.0 // off: any motion counts
    private val resumeRate = settings.magResumeTime?.let { 1.0 / it } ?: Double.POSITIVE_INFINITY
    private val budgeted = settings.magRejectionFactor != null
    private val rejectionFactor = settings.magRejectionFactor ?: 0.0
    private val reducedGain = if (budgeted) 1.0 / rejectionFactor else 1.0
    private val awaitsFirstField = settings.magFirstFieldTime != null
    private val firstFieldTime = settings.magFirstFieldTime ?: 0.0
    private val undisturbedTime = settings.magUndisturbedTime ?: 0.0 // off: a disturbance ends at once

    // After a disturbance the heading gain comes back as a ramp (magResumeTime), the bias estimate with it; a
    // disturbed field used after the hold's budget is spent enters at a reduced gain (magRejectionFactor).
    private val resumes = settings.magResumeTime != null
    private val scales = resumes || budgeted

    /** Steps whose reading was rejected as disturbed. */
    var rejections = 0L
        private set

    // Time the field has agreed with the reference without a break, s.
    private var agreeTime = 0.0

    // The hold's budget (magRejectionFactor on): time rejected, s; and whether it is spent.
    private var rejectTime = 0.0
    private var overBudget = false

    // Time since the field was last disturbed (or since a new reference), s; infinite before any disturbance.
    private var sinceDisturbed = Double.POSITIVE_INFINITY

    /** Fraction of the heading gain to apply to the current reading: 0 while disturbed, then a ramp up to 1 over magResumeTime. */
    val gainFactor: Double get() = when {
        disturbed -> if (overBudget) reducedGain else 0.0
        resumeRate == Double.POSITIVE_INFINITY -> 1.0
        else -> minOf(1.0, sinceDisturbed * resumeRate)
    }

    // A disturbed field's own running mean (the candidate for a new reference) and how long the
    // field has stayed within the tolerances of it.
    private var candNorm = 0.0
    private var candSinDip = 0.0
    private var steadyTime = 0.0

    private var hasReference = false
    private var refNorm = 0.0
    private var refSinDip = 0.0
    private var disturbedTime = 0.0

    var disturbed = false
        private set

    /** True when the last reading made a new reference (a new environment, not the first reading). */
    var newReference = false
        private set

    /** The next reading becomes the reference (the field as the filter sees it changed at once: HardIronEstimate). */
    fun forgetReference() {
        hasReference = false
    }

    /** True when the next reading will become the reference (so its raw dip is needed). */
    val needsReference: Boolean get() =
        (!hasReference && !awaitsFirstField) || (!budgeted && disturbedTime > maxRejectionTime)

    /**
     * Whether the held reading of [s] enters the step: its dip measured against the estimated up, or the
     * accelerometer's when [Step.accOk] and a new reference is taken; the squared bias-corrected rate for
     * magNewFieldMinGyro. Scales the heading gain ([gainFactor]) when magResumeTime or magRejectionFactor is
     * set; a new reference starts the heading's fast convergence again (without the resume ramp).
     */
    override fun check(s: Step) {
        if (!s.useMag) return
        val n2 = s.mx * s.mx + s.my * s.my + s.mz * s.mz
        val inv = MadgwickSteps.invSqrt(n2)
        val sinDip = -(s.mx * s.ux + s.my * s.uy + s.mz * s.uz) * inv
        val sinDipRaw = if (s.accOk && needsReference) -(s.mx * s.ax + s.my * s.ay + s.mz * s.az) * inv * MadgwickSteps.invSqrt(s.ax * s.ax + s.ay * s.ay + s.az * s.az) else sinDip
        if (!accept(s.dt, n2 * inv, sinDip, sinDipRaw, s.wx * s.wx + s.wy * s.wy + s.wz * s.wz)) {
            rejections++
            s.useMag = false
        }
        if (newReference && !resumes) s.newMagReference = true
        if (scales) s.headingFactor *= gainFactor
    }

    /**
     * Classifies one magnetometer reading of magnitude [norm] whose dip has sine [sinDip] (the
     * component of the unit field along the estimated down direction), or [sinDipRaw] measured
     * against the accelerometer, after [dt] s. Returns true when the reading may be used. The first
     * reading, and a field disturbed for longer than magMaxRejectionTime, become the reference; an
     * undisturbed field slowly updates it. With magNewFieldTime on, a disturbed field that stays
     * within the tolerances of its own running mean for that long becomes the reference too.
     */
    fun accept(dt: Double, norm: Double, sinDip: Double, sinDipRaw: Double, rate2: Double = Double.POSITIVE_INFINITY): Boolean {
        newReference = false
        if (needsReference) {
            newReference = hasReference
            if (hasReference) sinceDisturbed = 0.0
            refNorm = norm
            refSinDip = sinDipRaw
            hasReference = true
            disturbedTime = 0.0
            disturbed = false
            return true
        }
        if (!hasReference) {
            // magFirstFieldTime: the field is used while a steady one is awaited.
            followCandidate(norm, sinDip, rate2, dt)
            if (steadyTime >= firstFieldTime) {
                refNorm = candNorm
                refSinDip = candSinDip
                hasReference = true
                steadyTime = 0.0
            }
            return true
        }
        if (matches(norm, sinDip, refNorm, refSinDip)) {
            agreeTime += dt
            if (agreeTime >= undisturbedTime) disturbed = false
        } else {
            agreeTime = 0.0
            disturbed = true
        }
        if (disturbed && learnsNewField) {
            followCandidate(norm, sinDip, rate2, dt)
            if (steadyTime >= newFieldTime) {
                refNorm = candNorm
                refSinDip = candSinDip
                disturbed = false
                newReference = true
                sinceDisturbed = 0.0
            }
        }
        if (budgeted) {
            if (!disturbed) {
                rejectTime = maxOf(0.0, rejectTime - rejectionFactor * dt)
                overBudget = false
            } else if (rejectTime <= maxRejectionTime) {
                rejectTime += dt
                overBudget = false
            } else {
                overBudget = true
            }
        }
        if (disturbed) {
            disturbedTime += dt
            sinceDisturbed = 0.0
        } else {
            sinceDisturbed += dt
            disturbedTime = 0.0
            steadyTime = 0.0
            val k = minOf(1.0, dt * referenceRate)
            refNorm += k * (norm - refNorm)
            refSinDip += k * (sinDip - refSinDip)
        }
        return !disturbed || overBudget
    }

    // cos(δ − δ_ref) = cos δ cos δ_ref + sin δ sin δ_ref, with cos δ ≥ 0 for a dip in [−90°, 90°].
    /**
     * Follows the candidate field (a new reference, or the first one): a reading that matches the candidate adds
     * to its steady time (only time in motion counts, magNewFieldMinGyro) and moves the candidate's mean towards
     * it; any other reading starts a new candidate.
     */
    private fun followCandidate(norm: Double, sinDip: Double, rate2: Double, dt: Double) {
        if (steadyTime > 0.0 && matches(norm, sinDip, candNorm, candSinDip)) {
            if (rate2 >= newFieldMinGyro2) steadyTime += dt
            val k = minOf(1.0, dt / steadyTime)
            candNorm += k * (norm - candNorm)
            candSinDip += k * (sinDip - candSinDip)
        } else {
            candNorm = norm
            candSinDip = sinDip
            steadyTime = dt
        }
    }

    private fun matches(norm: Double, sinDip: Double, rNorm: Double, rSinDip: Double): Boolean =
        kotlin.math.abs(norm - rNorm) <= normTolerance * rNorm &&
            sqrt((1.0 - sinDip * sinDip) * (1.0 - rSinDip * rSinDip)) + sinDip * rSinDip >= cosDipTolerance

    override fun reset() = restore(NEW)

    /** The reference, the disturbance, the candidate field, the hold's budget and the count. */
    data class State(
        val hasReference: Boolean, val refNorm: Double, val refSinDip: Double, val disturbedTime: Double, val disturbed: Boolean,
        val candNorm: Double, val candSinDip: Double, val steadyTime: Double, val sinceDisturbed: Double, val agreeTime: Double,
        val rejectTime: Double, val overBudget: Boolean, val newReference: Boolean, val rejections: Long,
    )

    override fun state() = State(
        hasReference, refNorm, refSinDip, disturbedTime, disturbed, candNorm, candSinDip, steadyTime, sinceDisturbed, agreeTime,
        rejectTime, overBudget, newReference, rejections,
    )

    override fun restore(state: State) {
        hasReference = state.hasReference
        refNorm = state.refNorm
        refSinDip = state.refSinDip
        disturbedTime = state.disturbedTime
        disturbed = state.disturbed
        candNorm = state.candNorm
        candSinDip = state.candSinDip
        steadyTime = state.steadyTime
        sinceDisturbed = state.sinceDisturbed
        agreeTime = state.agreeTime
        rejectTime = state.rejectTime
        overBudget = state.overBudget
        newReference = state.newReference
        rejections = state.rejections
    }

    private companion object {
        val NEW = State(false, 0.0, 0.0, 0.0, false, 0.0, 0.0, 0.0, Double.POSITIVE_INFINITY, 0.0, 0.0, false, false, 0L)
    }
}
