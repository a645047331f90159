package dev.motionfusion.app.ui

import android.text.TextUtils
import android.view.View
import android.widget.TextView

/**
 * Sets [text] only when it differs from what the view shows: an unchanged text costs no layout
 * pass and sends accessibility services nothing. The live screen binds every text this way.
 */
internal fun TextView.setTextIfChanged(text: CharSequence) {
    if (!TextUtils.equals(this.text, text)) this.text = text
}

/**
 * A view's contentDescription that follows a value changing every frame without flooding
 * accessibility services: a new text is given to the view at most once per [minIntervalNs] of the
 * caller's clock (the live screen uses sample time), and at once when its [kind] changes (a heading
 * appearing or lost). The texts themselves should be rounded to what matters (whole degrees).
 */
internal class DescriptionThrottle(private val minIntervalNs: Long) {
    private var lastText: CharSequence? = null
    private var lastKind: Any? = null
    private var lastNs = 0L

    /** Descriptions given to the view so far (for tests). */
    var updates: Int = 0
        private set

    fun update(view: View, text: CharSequence?, nowNs: Long, kind: Any? = null) {
        if (TextUtils.equals(text, lastText)) return
        val due = updates == 0 || kind != lastKind || nowNs - lastNs >= minIntervalNs || nowNs < lastNs
        if (!due) return
        view.contentDescription = text
        lastText = text
        lastKind = kind
        lastNs = nowNs
        updates++
    }

    companion object {
        /** Two seconds: TalkBack reads a focused view's new description; more often is noise. */
        const val LIVE_INTERVAL_NS: Long = 2_000_000_000L
    }
}
