/*
 * The complete state of a MadgwickFilter, for restore(): the states of its stages (Stage.kt), each a
 * data class of its own, composed.
 */
package dev.motionfusion.core.filter

/**
 * The full state of a [MadgwickFilter] at one instant, with the settings it was taken under: an immutable
 * value (equal states, equal futures). Restoring it into a filter with the same settings continues exactly
 * as the original would, bit for bit.
 */
public data class FilterState internal constructor(
    public val settings: FilterSettings,
    /** The held readings, the clock and the counts (SampleGate). */
    internal val gate: SampleGate.State,
    /** q̂ and the flux reference (MadgwickSteps). */
    internal val estimate: MadgwickSteps.State,
    internal val bias: GyroBiasEstimate.State,
    internal val lowPass: AccelerometerLowPass.State,
    internal val recovery: InclinationRecovery.State,
    internal val heading: HeadingCorrection.State,
    /** The hard-iron estimate's (null when off). */
    internal val hardIron: HardIronEstimate.State?,
    /** The states of the filter's checks (Check), in the order of its list. */
    internal val checks: List<Any>,
)
