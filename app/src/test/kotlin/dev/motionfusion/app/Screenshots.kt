package dev.motionfusion.app

import android.app.Activity
import android.graphics.Bitmap
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.Rect
import android.view.View
import android.view.ViewGroup
import android.widget.TextView
import dev.motionfusion.app.ui.breaksInsideWord
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertTrue
import java.io.File

/**
 * Renders an activity's window to PNG (Robolectric native graphics) under the directory in
 * the `screenshots.dir` system property, so a person can look at each screen state, and
 * checks the picture is not blank.
 */
object Screenshots {
    /**
     * [systemBars]: the status bar's height (top) and the navigation bar's (bottom) the screen was
     * given as insets; they are painted over the picture as the phone would, so the picture shows
     * whether anything lies under them.
     */
    fun capture(activity: Activity, name: String, width: Int = 1080, height: Int = 1920, systemBars: Pair<Int, Int>? = null): Bitmap {
        val bitmap = render(activity.window.decorView, width, height)
        val canvas = Canvas(bitmap)
        if (systemBars != null) {
            val bar = android.graphics.Paint().apply { color = Color.argb(0xE0, 0, 0, 0) }
            canvas.drawRect(0f, 0f, width.toFloat(), systemBars.first.toFloat(), bar)
            canvas.drawRect(0f, (height - systemBars.second).toFloat(), width.toFloat(), height.toFloat(), bar)
        }
        write(bitmap, name)
        return bitmap
    }

    /** [root] laid out at [width] × [height] and drawn into a new bitmap. */
    private fun render(root: View, width: Int, height: Int): Bitmap {
        root.measure(
            View.MeasureSpec.makeMeasureSpec(width, View.MeasureSpec.EXACTLY),
            View.MeasureSpec.makeMeasureSpec(height, View.MeasureSpec.EXACTLY),
        )
        root.layout(0, 0, width, height)
        val bitmap = Bitmap.createBitmap(width, height, Bitmap.Config.ARGB_8888)
        root.draw(Canvas(bitmap))
        return bitmap
    }

    /** Writes [bitmap] as [name].png and checks it is not blank. */
    private fun write(bitmap: Bitmap, name: String) {
        val dir = File(System.getProperty("screenshots.dir") ?: "target/screenshots")
        dir.mkdirs()
        File(dir, "$name.png").outputStream().use { bitmap.compress(Bitmap.CompressFormat.PNG, 100, it) }
        assertTrue("$name rendered blank", distinctColours(bitmap) > 2)
    }

    /** Where [v] lies in its window's picture. */
    fun boundsInWindow(v: View): Rect {
        val at = IntArray(2).also(v::getLocationInWindow)
        return Rect(at[0], at[1], at[0] + v.width, at[1] + v.height)
    }

    /** The share of [area]'s pixels in [b] whose colour is within [tolerance] (per channel) of [colour]. */
    fun share(b: Bitmap, area: Rect, colour: Int, tolerance: Int = 12): Double {
        var n = 0
        var hits = 0
        for (y in area.top until area.bottom) for (x in area.left until area.right) {
            val p = b.getPixel(x, y)
            n++
            if (Math.abs(Color.red(p) - Color.red(colour)) <= tolerance && Math.abs(Color.green(p) - Color.green(colour)) <= tolerance &&
                Math.abs(Color.blue(p) - Color.blue(colour)) <= tolerance
            ) hits++
        }
        return if (n == 0) 0.0 else hits.toDouble() / n
    }

    /** Distinct colours (a sample of every 3rd pixel) in [area] of [b]. */
    fun colours(b: Bitmap, area: Rect): Int {
        val seen = HashSet<Int>()
        for (y in area.top until area.bottom step 3) for (x in area.left until area.right step 3) seen += b.getPixel(x, y) and Color.WHITE
        return seen.size
    }

    /**
     * Renders [dialog] over [activity] as the phone shows it: the activity at its configuration's
     * size, dimmed by the dialog's scrim, and the dialog's own window (a dialog lives in a window of
     * its own, which the activity's decor view does not draw) laid out as its window attributes
     * say (at most 560 dp wide, the Material 3 dialogs' limit) and centred. Returns the picture
     * and where the dialog's window lies in it.
     */
    fun captureDialog(activity: Activity, dialog: android.app.Dialog, name: String): Pair<Bitmap, Rect> {
        val c = activity.resources.configuration
        val d = activity.resources.displayMetrics.density
        val width = (c.screenWidthDp * d).toInt()
        val height = (c.screenHeightDp * d).toInt()
        val bitmap = render(activity.window.decorView, width, height)
        val canvas = Canvas(bitmap)
        val window = dialog.window!!
        val dim = if (window.attributes.flags and android.view.WindowManager.LayoutParams.FLAG_DIM_BEHIND != 0) window.attributes.dimAmount else 0f
        canvas.drawColor(Color.argb((255 * dim).toInt(), 0, 0, 0))
        val decor = window.decorView
        val maxWidth = minOf(width, (560 * d).toInt())
        val widthSpec = when (val w = window.attributes.width) {
            android.view.ViewGroup.LayoutParams.MATCH_PARENT -> View.MeasureSpec.makeMeasureSpec(maxWidth, View.MeasureSpec.EXACTLY)
            android.view.ViewGroup.LayoutParams.WRAP_CONTENT -> View.MeasureSpec.makeMeasureSpec(maxWidth, View.MeasureSpec.AT_MOST)
            else -> View.MeasureSpec.makeMeasureSpec(minOf(w, width), View.MeasureSpec.EXACTLY)
        }
        decor.measure(widthSpec, View.MeasureSpec.makeMeasureSpec(height, View.MeasureSpec.AT_MOST))
        val left = (width - decor.measuredWidth) / 2
        val top = (height - decor.measuredHeight) / 2
        decor.layout(left, top, left + decor.measuredWidth, top + decor.measuredHeight)
        canvas.save()
        canvas.translate(left.toFloat(), top.toFloat())
        decor.draw(canvas)
        canvas.restore()
        write(bitmap, name)
        return bitmap to Rect(left, top, left + decor.measuredWidth, top + decor.measuredHeight)
    }

    /**
     * Renders [activity] at the size its configuration gives (the qualifiers' screen in dp times
     * the density) and checks its layout with [assertLaidOut].
     */
    fun captureScreen(activity: Activity, name: String): Bitmap {
        val c = activity.resources.configuration
        val d = activity.resources.displayMetrics.density
        val bitmap = capture(activity, name, width = (c.screenWidthDp * d).toInt(), height = (c.screenHeightDp * d).toInt())
        assertLaidOut(activity, name)
        assertAccessible(activity, name)
        return bitmap
    }

    /**
     * Renders [activity] at its configuration's width and as tall as its content, every scroll
     * view unrolled: the whole of a long form in one picture (no layout check: nothing is hidden).
     */
    fun captureWhole(activity: Activity, name: String): Bitmap {
        val c = activity.resources.configuration
        val d = activity.resources.displayMetrics.density
        val width = (c.screenWidthDp * d).toInt()
        val root = activity.window.decorView
        val screen = (c.screenHeightDp * d).toInt()
        root.measure(View.MeasureSpec.makeMeasureSpec(width, View.MeasureSpec.EXACTLY), View.MeasureSpec.makeMeasureSpec(screen, View.MeasureSpec.EXACTLY))
        var extra = 0
        fun walk(v: View) {
            if (v is android.widget.ScrollView && v.childCount > 0) extra += (v.getChildAt(0).measuredHeight - v.measuredHeight).coerceAtLeast(0)
            if (v is ViewGroup) for (i in 0 until v.childCount) walk(v.getChildAt(i))
        }
        walk(root)
        return capture(activity, name, width = width, height = screen + extra)
    }

    /**
     * Every text shown lies within the screen's width, is not cut short (no ellipsis) nor broken
     * inside a word ("St/op": too narrow a button) and overlaps no other text where it is seen.
     */
    fun assertLaidOut(activity: Activity, name: String) {
        val root = activity.window.decorView
        val texts = ArrayList<Pair<TextView, Rect>>()
        val seen = ArrayList<Pair<TextView, Rect>>()
        fun walk(v: View) {
            if (v.visibility != View.VISIBLE) return
            if (v is TextView && v.text.isNotEmpty() && v.width > 0 && v.height > 0) {
                val at = IntArray(2)
                v.getLocationInWindow(at)
                texts += v to Rect(at[0], at[1], at[0] + v.width, at[1] + v.height)
                // What is seen of it: a scrolled-away part is clipped by its scroll view.
                val visible = Rect()
                if (v.getGlobalVisibleRect(visible)) seen += v to visible
            }
            if (v is ViewGroup) for (i in 0 until v.childCount) walk(v.getChildAt(i))
        }
        walk(root)
        assertTrue("$name: no text on screen", texts.isNotEmpty())
        for ((v, r) in texts) {
            val what = "$name: '${v.text.take(40)}'"
            assertTrue("$what lies outside the screen's width: $r (width ${root.width})", r.left >= 0 && r.right <= root.width)
            val layout = v.layout
            if (layout != null) for (line in 0 until layout.lineCount) assertEquals("$what is cut short", 0, layout.getEllipsisCount(line))
            assertFalse("$what breaks inside a word", v.breaksInsideWord())
        }
        // Buttons of a group (MaterialButtonToggleGroup) share their 1-dp border: that is no overlap.
        val border = Math.ceil(activity.resources.displayMetrics.density.toDouble()).toInt()
        for (i in seen.indices) for (j in i + 1 until seen.size) {
            val (a, ra) = seen[i]
            val (b, rb) = seen[j]
            val common = Rect()
            // A snackbar floats above the screen's texts by design (the settings' Undo): only its own texts must not overlap.
            if (a.isSnackbarText() != b.isSnackbarText()) continue
            val overlap = common.setIntersect(ra, rb) && minOf(common.width(), common.height()) > border
            assertFalse("$name: '${a.text.take(30)}' $ra overlaps '${b.text.take(30)}' $rb", overlap)
        }
    }

    private fun View.isSnackbarText(): Boolean =
        id == com.google.android.material.R.id.snackbar_text || id == com.google.android.material.R.id.snackbar_action

    /** [A11yChecks] on the screen as rendered: labels, touch targets and text contrast. */
    fun assertAccessible(activity: Activity, name: String) {
        assertEquals("$name: accessibility", "", A11yChecks.problems(activity).joinToString("\n"))
    }

    private fun distinctColours(b: Bitmap): Int {
        val seen = HashSet<Int>()
        for (y in 0 until b.height step 7) for (x in 0 until b.width step 7) {
            seen += b.getPixel(x, y) and Color.WHITE
            if (seen.size > 16) return seen.size
        }
        return seen.size
    }
}
