package android.support.v4.view

import android.content.Context
import android.view.View
import android.view.ViewGroup

/*
 * The two calls and the one class of the old support library that the view checks of Google's
 * Accessibility Test Framework 2.1 (the newest on Maven Central, A11yChecks) reach: the support
 * library itself is only on Google's Maven repository. Each forwards to the framework, which has
 * had them since API 16.
 */

/** ATF's ViewAccessibilityUtils reads a view's alpha and live region through it. */
object ViewCompat {
    @JvmStatic
    fun getAlpha(view: View): Float = view.alpha

    @JvmStatic
    fun getAccessibilityLiveRegion(view: View): Int = view.accessibilityLiveRegion
}

/** Named (never made) by ATF's speakable-text check, whose pages it skips; the app has none. */
abstract class ViewPager(context: Context) : ViewGroup(context)
