package dev.motionfusion.app

import android.app.Activity
import android.graphics.Bitmap
import android.graphics.Canvas
import android.graphics.Color
import android.view.View
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

    private fun distinctColours(b: Bitmap): Int {
        val seen = HashSet<Int>()
        for (y in 0 until b.height step 7) for (x in 0 until b.width step 7) {
            seen += b.getPixel(x, y) and Color.WHITE
            if (seen.size > 16) return seen.size
        }
        return seen.size
    }
}
