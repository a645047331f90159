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
    fun capture(activity: Activity, name: String, width: Int = 1080, height: Int = 1920): Bitmap {
        val root: View = activity.window.decorView
        root.measure(
            View.MeasureSpec.makeMeasureSpec(width, View.MeasureSpec.EXACTLY),
            View.MeasureSpec.makeMeasureSpec(height, View.MeasureSpec.EXACTLY),
        )
        root.layout(0, 0, width, height)
        val bitmap = Bitmap.createBitmap(width, height, Bitmap.Config.ARGB_8888)
        root.draw(Canvas(bitmap))
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
