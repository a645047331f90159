package dev.motionfusion.app.ui

import android.view.View
import androidx.activity.ComponentActivity
import androidx.activity.enableEdgeToEdge
import androidx.core.view.ViewCompat
import androidx.core.view.WindowInsetsCompat
import androidx.core.view.updatePadding

/**
 * Draws the activity edge to edge (what targetSdk 35 imposes on Android 15) and keeps [content]
 * clear of the system bars, the display cutout and the keyboard by adding their insets to the
 * padding it was laid out with. Every screen calls it after setContentView.
 */
internal fun ComponentActivity.fitToSystemBars(content: View) {
    enableEdgeToEdge()
    val start = content.paddingLeft
    val top = content.paddingTop
    val end = content.paddingRight
    val bottom = content.paddingBottom
    ViewCompat.setOnApplyWindowInsetsListener(content) { v, insets ->
        val bars = insets.getInsets(
            WindowInsetsCompat.Type.systemBars() or WindowInsetsCompat.Type.displayCutout() or WindowInsetsCompat.Type.ime(),
        )
        v.updatePadding(left = start + bars.left, top = top + bars.top, right = end + bars.right, bottom = bottom + bars.bottom)
        WindowInsetsCompat.CONSUMED
    }
    ViewCompat.requestApplyInsets(content)
}
