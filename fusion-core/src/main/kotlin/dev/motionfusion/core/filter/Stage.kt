/*
 * What the filter is composed of: stages (MadgwickFilter.kt lists them in their order) that share one
 * [Step], the values of the gyroscope step under way. Units SI, device frame, as in MadgwickFilter.kt.
 */
package dev.motionfusion.core.filter

/**
 * One mechanism of the filter, with its own settings, its own state and nothing else.
 *
 * The contract, for a stage added to the filter (a disturbance detector, a heading trust, ...):
 * - **Settings**: taken from [FilterSettings] in the constructor and kept as `val`s; the stage is built
 *   only when its setting turns it on (the composition holds `null`, or leaves it out of its list, when off),
 *   so a stage never tests "is it off" per sample.
 * - **State**: every `var` that outlives one step belongs to the stage and to no one else: only the stage
 *   writes it (others call its methods). [state] returns all of it as an immutable value, a data class of
 *   the stage's own ([S]), so that equal states mean equal futures; [restore] takes such a value back.
 *   A filter stopped and resumed by FilterState continues bit for bit (StopResumeTest) only if nothing is
 *   left out of [S].
 * - **[reset]**: back to the state of a new stage with the same settings.
 * - **Hot path**: the per-sample methods allocate nothing (no boxing, no lambdas, no collections); only
 *   [state] allocates.
 */
internal interface Stage<S : Any> {
    /** All of the stage's state, as an immutable value (allocates; not for every sample). */
    fun state(): S

    /** Takes back a state [state] returned by a stage with the same settings. */
    fun restore(state: S)

    /** Back to the state of a new stage with the same settings. */
    fun reset()
}

/**
 * A stage that decides, once a step, whether the held readings enter it: a disturbance detector. It reads
 * the [Step] (the readings, whether they are fresh, the estimated up, the bias-corrected rate) and may
 * clear [Step.useAcc] or [Step.useMag], scale [Step.headingFactor] (multiply, never set) and set
 * [Step.newMagReference]. A check whose reading is already left out ([Step.useAcc] or [Step.useMag] false)
 * should not count it again.
 *
 * Adding one: a new file with the class, and one line in MadgwickFilter's list `checks` (its place in the
 * list is its place in the step, and in FilterState.checks). FilterStageTest shows it with a toy detector.
 */
internal interface Check<S : Any> : Stage<S> {
    /** Decides on the step [s] (after the bias's rest estimate, before the low-pass and the gain). */
    fun check(s: Step)
}

/** [Stage.restore] for a state whose type the caller knows only from the stage it came from. */
@Suppress("UNCHECKED_CAST")
internal fun <S : Any> Stage<S>.restoreAny(state: Any) = restore(state as S)

/**
 * The values of one gyroscope step that the stages read and write. One instance per filter, reused for
 * every step (allocation-free). The held accelerometer and magnetometer readings live here (SampleGate
 * holds them and keeps them in its state); the rest is set anew each step, in this order: SampleGate
 * (timing, freshness, the gyroscope reading), the filter (estimated up, bias-corrected rate, use flags
 * reset), the checks (what enters, heading factor).
 */
internal class Step {
    /** Step length, s. */
    @JvmField var dt = 0.0

    /** The gyroscope reading, rad/s, and the same with the bias estimate removed. */
    @JvmField var gx = 0.0
    @JvmField var gy = 0.0
    @JvmField var gz = 0.0
    @JvmField var wx = 0.0
    @JvmField var wy = 0.0
    @JvmField var wz = 0.0

    /** The held accelerometer (m/s²) and magnetometer (µT) readings. */
    @JvmField var ax = 0.0
    @JvmField var ay = 0.0
    @JvmField var az = 0.0
    @JvmField var mx = 0.0
    @JvmField var my = 0.0
    @JvmField var mz = 0.0

    /** The held readings are valid and no older than maxGap. */
    @JvmField var accOk = false
    @JvmField var magOk = false

    /** The held magnetometer reading is finite, in range and no older than maxGap, even if too strong for a heading (HardIronEstimate's). */
    @JvmField var magFresh = false

    /** The estimated up in the sensor frame before the step (unit). */
    @JvmField var ux = 0.0
    @JvmField var uy = 0.0
    @JvmField var uz = 0.0

    /** Whether the readings enter this step (start as accOk, magOk; the checks may clear them). */
    @JvmField var useAcc = false
    @JvmField var useMag = false

    /** The heading gain's factor this step (1; the checks multiply theirs in). */
    @JvmField var headingFactor = 1.0

    /** The bias estimate in motion's own factor this step, on top of the heading gain's (1; the checks multiply theirs in). */
    @JvmField var biasFactor = 1.0

    /** A check took a new magnetic reference: the heading's fast convergence starts again. */
    @JvmField var newMagReference = false
}
