package dev.motionfusion.app.ui

import android.view.View
import android.view.ViewGroup
import android.widget.LinearLayout
import android.widget.TextView

/** Some line of this text ends inside a word ("St|op", "Download|s"): the view is too narrow for it. */
internal fun TextView.breaksInsideWord(): Boolean {
    val l = layout ?: return false
    val t = text
    for (line in 0 until l.lineCount - 1) {
        val end = l.getLineEnd(line)
        if (end in 1 until t.length && t[end - 1].isLetterOrDigit() && t[end].isLetterOrDigit()) return true
    }
    return false
}

/** Some line of this text is cut short with an ellipsis. */
internal fun TextView.isCutShort(): Boolean {
    val l = layout ?: return false
    return (0 until l.lineCount).any { l.getEllipsisCount(it) > 0 }
}

/**
 * Lays the children of the horizontal [row] one under the other, each as wide as the row (a switch keeps
 * its own width, at the start), once side by side one of them does not fit: a text cut short or broken
 * inside a word, or a child reaching past the row's edge (a large font size, a long translation). Until then the row is as its layout says. Stacked,
 * it stays stacked while the screen lives (a configuration change makes a new one). Works for any
 * LinearLayout, MaterialButtonToggleGroup included (it draws its vertical segments itself).
 */
internal fun stackWhenCrowded(row: LinearLayout, gapDp: Int = 6) {
    row.addOnLayoutChangeListener(object : View.OnLayoutChangeListener {
        override fun onLayoutChange(v: View, l: Int, t: Int, r: Int, b: Int, ol: Int, ot: Int, or: Int, ob: Int) {
            if (row.orientation == LinearLayout.VERTICAL || !crowded(row)) return
            row.removeOnLayoutChangeListener(this)
            val gap = (gapDp * row.resources.displayMetrics.density).toInt()
            row.orientation = LinearLayout.VERTICAL
            var first = true
            for (i in 0 until row.childCount) {
                val child = row.getChildAt(i)
                val lp = child.layoutParams as LinearLayout.LayoutParams
                // Buttons take the width; a switch (a CompoundButton) keeps its own, at the start, next to its label's line.
                if (lp.weight > 0f || lp.width == 0 || (child is android.widget.Button && child !is android.widget.CompoundButton)) {
                    lp.width = ViewGroup.LayoutParams.MATCH_PARENT
                    lp.weight = 0f
                }
                if (lp.height == ViewGroup.LayoutParams.MATCH_PARENT) lp.height = ViewGroup.LayoutParams.WRAP_CONTENT
                lp.marginStart = 0
                lp.marginEnd = 0
                if (child.visibility != View.GONE) {
                    if (!first) lp.topMargin = gap
                    first = false
                }
                child.layoutParams = lp
            }
            // Not within this layout pass: the next one lays the stack out.
            row.post { row.requestLayout() }
        }
    })
}

private fun crowded(row: LinearLayout): Boolean {
    for (i in 0 until row.childCount) {
        val child = row.getChildAt(i)
        if (child.visibility == View.GONE) continue
        if (child.left < 0 || child.right > row.width) return true
        if (child is TextView && (child.isCutShort() || child.breaksInsideWord())) return true
    }
    return false
}
