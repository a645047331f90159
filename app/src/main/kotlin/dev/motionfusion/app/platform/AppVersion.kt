package dev.motionfusion.app.platform

import android.content.Context

/** The app's version name, as the manifest gives it ("" when the package manager has none): meta.json, the stream's hello, a calibration's origin. */
internal object AppVersion {
    fun of(context: Context): String = try {
        context.packageManager.getPackageInfo(context.packageName, 0).versionName ?: ""
    } catch (_: Exception) {
        ""
    }
}
