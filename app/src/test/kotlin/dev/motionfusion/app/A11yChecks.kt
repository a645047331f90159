package dev.motionfusion.app

import android.app.Activity
import android.graphics.Color
import android.graphics.Typeface
import android.graphics.drawable.ColorDrawable
import android.graphics.drawable.Drawable
import android.util.TypedValue
import android.view.View
import android.view.ViewGroup
import android.widget.AdapterView
import android.widget.CompoundButton
import android.widget.EditText
import android.widget.ImageView
import android.widget.TextView
import androidx.core.graphics.ColorUtils
import com.google.android.apps.common.testing.accessibility.framework.AccessibilityCheckPreset
import com.google.android.apps.common.testing.accessibility.framework.AccessibilityCheckResult
import com.google.android.material.button.MaterialButton
import com.google.android.material.card.MaterialCardView
import com.google.android.material.shape.MaterialShapeDrawable
import com.google.android.material.slider.Slider

/**
 * The accessibility checks run on every screen the tests render (Screenshots.captureScreen): the
 * view checks of Google's Accessibility Test Framework 2.1, the newest on Maven Central (touch
 * target size, text contrast, speakable text, duplicate clickable bounds, clickable spans,
 * descriptions of editable fields, redundant descriptions; the two support-library calls they
 * make are forwarded by `android.support.v4.view` in the tests), errors only; and the project's
 * own, which also read what ATF 2.1 does not (Material shapes and cards as backgrounds,
 * translucent text):
 * - **labels**: every view a person can act on (clickable, long-clickable, a switch or a slider)
 *   and every picture the app draws itself (its own views, images) has a name TalkBack reads:
 *   its text, its contentDescription, or a hint; a clickable group is named by its texts;
 * - **touch targets**: every view a person can act on is at least 48 × 48 dp;
 * - **contrast**: every enabled text has a contrast of at least 4.5:1 with what is behind it (3:1
 *   for large text: 18 sp, or 14 sp bold), the background found as the first plain colour behind
 *   it (a colour drawable, a Material shape's fill, a card's colour, a filled button's tint, the
 *   window's background); a text over a background of another kind (a picture, a ripple without
 *   fill) is not judged.
 * Returns the problems found, one line each.
 */
internal object A11yChecks {
    fun problems(activity: Activity): List<String> = atf(activity.window.decorView) + own(activity)

    /** ATF's view checks of its LATEST preset (touch target, contrast, speakable text, duplicate bounds, spans, descriptions). */
    private val atfChecks = AccessibilityCheckPreset.getViewChecksForPreset(AccessibilityCheckPreset.LATEST).toList()

    fun atf(root: View): List<String> = atfChecks.flatMap { check ->
        check.runCheckOnViewHierarchy(root).filter { it.type == AccessibilityCheckResult.AccessibilityCheckResultType.ERROR }.map { r ->
            val v = r.view
            val id = v?.let { runCatching { it.resources.getResourceEntryName(it.id) }.getOrNull() ?: it.javaClass.simpleName }
            "ATF ${check.javaClass.simpleName}: $id: ${r.message}"
        }
    }

    private fun own(activity: Activity): List<String> {
        val out = ArrayList<String>()
        val density = activity.resources.displayMetrics.density
        val windowBackground = colourOf(activity.window.decorView.background) ?: themeBackground(activity)
        fun name(v: View) = runCatching { v.resources.getResourceEntryName(v.id) }.getOrNull() ?: v.javaClass.simpleName
        fun walk(v: View) {
            if (v.visibility != View.VISIBLE || v.width == 0 || v.height == 0) return
            if (!v.isShown) return
            // A list is acted on through its items (checked as they are), not as a control of its own.
            val actionable = (v.isClickable || v.isLongClickable || v is CompoundButton || v is Slider) && v.isEnabled && v !is AdapterView<*>
            if (actionable && v.isImportantForAccessibility && label(v).isNullOrBlank()) out += "${name(v)}: a control without a label"
            val ownDrawing = v.javaClass.name.startsWith("dev.motionfusion.app") && v !is ViewGroup && v !is TextView
            if ((ownDrawing || (v is ImageView && v.importantForAccessibility != View.IMPORTANT_FOR_ACCESSIBILITY_NO && v.drawable != null)) && v.contentDescription.isNullOrBlank()) {
                out += "${name(v)}: a picture without a description"
            }
            if (actionable) {
                val w = v.width / density
                val h = v.height / density
                if (w < 47.5f || h < 47.5f) out += "${name(v)}: touch target %.0f × %.0f dp, under 48 × 48".format(w, h)
            }
            if (v is TextView && v !is EditText && v.text.isNotBlank() && v.isEnabled) {
                val behind = background(v, windowBackground)
                if (behind != null) {
                    val fg = ColorUtils.compositeColors(v.currentTextColor, behind)
                    val ratio = ColorUtils.calculateContrast(fg, behind)
                    val sp = v.textSize / TypedValue.applyDimension(TypedValue.COMPLEX_UNIT_SP, 1f, v.resources.displayMetrics)
                    val bold = v.typeface?.isBold == true || (v.typeface?.style ?: Typeface.NORMAL) and Typeface.BOLD != 0
                    val large = sp >= 18f || (sp >= 14f && bold)
                    val needed = if (large) 3.0 else 4.5
                    if (ratio < needed) {
                        out += "${name(v)} '${v.text.take(30)}': contrast %.2f:1 (text %s on %s), under %.1f:1".format(
                            ratio, Integer.toHexString(fg), Integer.toHexString(behind), needed,
                        )
                    }
                }
            }
            if (v is ViewGroup) for (i in 0 until v.childCount) walk(v.getChildAt(i))
        }
        walk(activity.window.decorView)
        return out
    }

    /** What TalkBack reads for [v]: its description, its text or hint, or a group's texts. */
    private fun label(v: View): CharSequence? {
        v.contentDescription?.takeIf { it.isNotBlank() }?.let { return it }
        if (v is TextView) {
            v.text?.takeIf { it.isNotBlank() }?.let { return it }
            v.hint?.takeIf { it.isNotBlank() }?.let { return it }
        }
        if (v is ViewGroup) {
            val texts = StringBuilder()
            fun collect(c: View) {
                if (c.visibility != View.VISIBLE) return
                if (c is TextView) texts.append(c.text)
                c.contentDescription?.let { texts.append(it) }
                if (c is ViewGroup) for (i in 0 until c.childCount) collect(c.getChildAt(i))
            }
            collect(v)
            return texts.takeIf { it.isNotBlank() }
        }
        return null
    }

    /** The first plain colour behind [v] (its own background included), or null when what lies behind is not one colour. */
    private fun background(v: View, window: Int): Int? {
        var c: View? = v
        while (c != null) {
            val own = when {
                c is MaterialButton -> c.backgroundTintList?.getColorForState(c.drawableState, Color.TRANSPARENT)?.takeIf { Color.alpha(it) > 0 }
                c is MaterialCardView -> c.cardBackgroundColor.getColorForState(c.drawableState, Color.TRANSPARENT).takeIf { Color.alpha(it) > 0 }
                else -> null
            }
            if (own != null) return opaque(own, c, window)
            val d = c.background
            if (d != null && c !is MaterialButton) {
                val colour = colourOf(d) ?: return null
                if (Color.alpha(colour) > 0) return opaque(colour, c, window)
            }
            c = c.parent as? View
        }
        return window
    }

    /** A translucent [colour] of [view] laid over what is behind the view. */
    private fun opaque(colour: Int, view: View, window: Int): Int =
        if (Color.alpha(colour) == 255) colour else ColorUtils.compositeColors(colour, (view.parent as? View)?.let { background(it, window) } ?: window)

    /** The colour of a plain drawable, or null for any other kind. */
    private fun colourOf(d: Drawable?): Int? = when (d) {
        null -> null
        is ColorDrawable -> d.color
        is MaterialShapeDrawable -> d.fillColor?.defaultColor ?: Color.TRANSPARENT
        else -> null
    }

    private fun themeBackground(a: Activity): Int {
        val tv = TypedValue()
        a.theme.resolveAttribute(android.R.attr.colorBackground, tv, true)
        return tv.data
    }
}
