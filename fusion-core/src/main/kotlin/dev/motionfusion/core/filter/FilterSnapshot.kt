/*
 * An immutable copy of the complete state of a MadgwickFilter, for restore().
 */
package dev.motionfusion.core.filter

/**
 * The full state of a [MadgwickFilter] at one instant, with the settings it was taken under.
 * Restoring it into a filter with the same settings continues exactly as the original would.
 */
public class FilterSnapshot internal constructor(
    public val settings: FilterSettings,
    private val doubles: DoubleArray,
    private val longs: LongArray,
) {
    internal fun doubles(): DoubleArray = doubles.copyOf()
    internal fun longs(): LongArray = longs.copyOf()

    override fun equals(other: Any?): Boolean = other is FilterSnapshot && settings == other.settings &&
        doubles.contentEquals(other.doubles) && longs.contentEquals(other.longs)

    override fun hashCode(): Int = 31 * (31 * settings.hashCode() + doubles.contentHashCode()) + longs.contentHashCode()
}
