package dev.motionfusion.app

import android.app.Activity
import android.graphics.Bitmap
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.Rect
import android.view.View
import android.view.ViewGroup
import android.widget.TextView
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
        val root: View = activity.window.decorView
        root.measure(
            View.MeasureSpec.makeMeasureSpec(width, View.MeasureSpec.EXACTLY),
            View.MeasureSpec.makeMeasureSpec(height, View.MeasureSpec.EXACTLY),
        )
        root.layout(0, 0, width, height)
        val bitmap = Bitmap.createBitmap(width, height, Bitmap.Config.ARGB_8888)
        val canvas = Canvas(bitmap)
        root.draw(canvas)
        if (systemBars != null) {
            val bar = android.graphics.Paint().apply { color = Color.argb(0xE0, 0, 0, 0) }
            canvas.drawRect(0f, 0f, width.toFloat(), systemBars.first.toFloat(), bar)
            canvas.drawRect(0f, (height - systemBars.second).toFloat(), width.toFloat(), height.toFloat(), bar)
        }
        val dir = File(System.getProperty("screenshots.dir") ?: "target/screenshots")
        dir.mkdirs()
        File(dir, "$name.png").outputStream().use { bitmap.compress(Bitmap.CompressFormat.PNG, 100, it) }
        assertTrue("$name rendered blank", distinctColours(bitmap) > 2)
        return bitmap
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
     * Every text shown lies within the screen's width, is not cut short (no ellipsis) and
     * overlaps no other text where it is seen.
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
        }
        for (i in seen.indices) for (j in i + 1 until seen.size) {
            val (a, ra) = seen[i]
            val (b, rb) = seen[j]
            assertFalse("$name: '${a.text.take(30)}' $ra overlaps '${b.text.take(30)}' $rb", Rect.intersects(ra, rb))
        }
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
