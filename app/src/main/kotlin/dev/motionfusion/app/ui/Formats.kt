package dev.motionfusion.app.ui

import android.content.Context
import java.math.RoundingMode
import java.text.NumberFormat
import java.util.Locale

/** Numbers as the user's language writes them (decimal comma in German). */
internal object Formats {
    /** The locale the resources of [c] are in (that of its configuration, which getString formats with). */
    fun locale(c: Context): Locale = c.resources.configuration.locales[0] ?: Locale.getDefault()

    /** [v] with at most [decimals] decimals, trailing zeros dropped, in the locale's digits and decimal mark. */
    fun number(c: Context, v: Double, decimals: Int): String = NumberFormat.getNumberInstance(locale(c)).apply {
        maximumFractionDigits = decimals
        minimumFractionDigits = 0
        isGroupingUsed = false
        roundingMode = RoundingMode.HALF_EVEN
    }.format(v)

    /**
     * [format] of [v] in the locale of [c], kept in place among separators and units: a number in Arabic digits
     * is isolated (LRI … PDI), as the bidirectional algorithm would otherwise reorder two of them joined by a
     * separator ("150,800 · 200.0" shown as "200.0 · 150,800"); in Latin digits it is left as it is.
     */
    fun isolated(c: Context, format: String, v: Any): String = String.format(locale(c), format, v).let { n ->
        if (n.any { Character.getDirectionality(it) == Character.DIRECTIONALITY_ARABIC_NUMBER }) "\u2066$n\u2069" else n
    }

    /** A gap between a recording's parts, "0:42" (unknown: "—"). */
    fun gap(gapNs: Long?): String = gapNs?.let { android.text.format.DateUtils.formatElapsedTime((it / 1_000_000_000L).coerceAtLeast(0)) } ?: "—"
}
